"""An inline search opens its bag once: the "is it small" estimate and the search share the opening."""

from __future__ import annotations

from typing import Any

import pytest
from mcp import Client

from bagmcp_shared.access import BagAccess
from tests.fixtures.call_spy import first_arguments
from tests.fixtures.inprocess import InProcess
from tests.fixtures.mcp_client import call

pytestmark = pytest.mark.anyio


@pytest.fixture
def openings(served: InProcess, monkeypatch: pytest.MonkeyPatch) -> list[str]:
    """The bags opened through the services' access layer while the test runs (the real opening still runs)."""
    access: BagAccess = served.composition.embedded.resources.access
    return first_arguments(monkeypatch, access, "open")


@pytest.mark.parametrize(
    "arguments",
    [
        {"topic": "/odom", "condition": "near_position", "value": {"x": 0, "y": 0, "radius": 100}},  # the index
        {"topic": "/rosout", "condition": "contains", "value": "obstacle"},  # decoded: a short topic
    ],
)
async def test_an_inline_search_opens_its_bag_once(
    served: InProcess, openings: list[str], arguments: dict[str, Any]
) -> None:
    async with Client(served.service("bag-store"), cache=None) as client:
        answer = await call(client, "search_messages", bag="scenario_mcap", **arguments)
    assert answer["result"]["total"] >= 1  # answered inline, not as a job
    assert openings == ["scenario_mcap"]
