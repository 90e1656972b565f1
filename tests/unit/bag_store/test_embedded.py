"""The embedded bag-store keeps each bag it ingested open (while the cache has room), so the first question
about a bag does not pay for opening it."""

from __future__ import annotations

import time
from pathlib import Path

import pytest
from mcp import Client

from bagmcp_shared.settings import OpenBagLimits
from tests.fixtures.bagfactory import BAG_KINDS, BagKind
from tests.fixtures.inprocess import InProcess, copy_bags, in_process
from tests.fixtures.mcp_client import call

pytestmark = pytest.mark.anyio


def _warmed(services: InProcess, count: int) -> None:
    """Warming follows ingest on the ingest thread: wait for it (bounded)."""
    cache = services.composition.embedded.resources.access.cache
    deadline = time.monotonic() + 30
    while cache.opened < count and time.monotonic() < deadline:
        time.sleep(0.02)


async def test_the_first_question_after_ingest_finds_the_bag_open(
    scenario_bags: dict[BagKind, Path], tmp_path: Path
) -> None:
    folder = copy_bags(list(scenario_bags.values()), tmp_path / "bags")
    with in_process(folder, tmp_path / "data") as services:
        _warmed(services, len(BAG_KINDS))
        cache = services.composition.embedded.resources.access.cache
        assert (len(cache), cache.opened) == (len(BAG_KINDS), len(BAG_KINDS))
        async with Client(services.service("bag-store"), cache=None) as client:
            for name in ("scenario", "scenario_db3", "scenario_mcap"):
                message = await call(client, "get_message_at_time", bag=name, topic="/odom", time=1.0)
                assert message["message"]["time"]["offset_s"] == pytest.approx(1.0)
        assert cache.opened == len(BAG_KINDS)  # answered by the readers ingest left open


async def test_a_full_cache_is_not_churned_by_warming(scenario_bags: dict[BagKind, Path], tmp_path: Path) -> None:
    folder = copy_bags(list(scenario_bags.values()), tmp_path / "bags")
    with in_process(folder, tmp_path / "data", open_bags=OpenBagLimits(max_bags=1)) as services:
        _warmed(services, 1)
        time.sleep(0.2)  # the other bags' warming (which must not happen) would be done by now
        cache = services.composition.embedded.resources.access.cache
        assert (len(cache), cache.opened) == (1, 1)
