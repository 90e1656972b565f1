"""search_messages and jobs through `bagmcp serve` (embedded), plus index-vs-bag equivalence."""

from __future__ import annotations

import shutil
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from bagmcp_bag_store.embedded import start_embedded
from bagmcp_bag_store.filtering import FilterParams, filter_bag
from bagmcp_bag_store.queries.search import search_messages
from bagmcp_bag_store.queries.search_params import SearchParams
from bagmcp_kit.runtime.resources import embedded_resources
from bagmcp_shared.jobs import Unreported
from tests.checks.search_checks import (
    check_cancel_stops_a_running_job,
    check_search,
    check_slow_search_becomes_a_job_with_progress,
    finished,
)
from tests.fixtures import scenario as sc
from tests.fixtures.bagfactory import BagKind, write_chatter_bag
from tests.fixtures.mcp_client import call, http_client, ingested_bags
from tests.fixtures.processes import BIN, http_ok, service, wait_until
from tests.fixtures.servers import free_port
from tests.integration.bag_downloads import download_info

pytestmark = pytest.mark.anyio
BAGS = ["scenario", "scenario_db3", "scenario_mcap"]
CHATTER_MESSAGES = 300_000


@pytest.fixture(scope="module")
def folder(scenario_bags: dict[BagKind, Path], tmp_path_factory: pytest.TempPathFactory) -> Path:
    folder = tmp_path_factory.mktemp("served-search")
    for path in scenario_bags.values():
        (shutil.copytree if path.is_dir() else shutil.copy)(path, folder / path.name)
    write_chatter_bag(folder, count=CHATTER_MESSAGES)
    return folder


@pytest.fixture(scope="module")
def served(folder: Path, tmp_path_factory: pytest.TempPathFactory) -> Iterator[str]:
    port = free_port()
    url = f"http://127.0.0.1:{port}"
    env = {"BAGMCP_JOB_BUDGET_S": "0.3", "BAGMCP_DATA_DIR": str(tmp_path_factory.mktemp("data"))}
    with service(
        "serve-search",
        [str(BIN / "bagmcp"), "serve", "--bags", str(folder), "--port", str(port)],
        env=env,
        log_dir=tmp_path_factory.mktemp("logs"),
        ready=http_ok(f"{url}/healthz"),
    ):
        yield f"{url}/mcp"


async def test_search_answers_on_three_formats_through_the_embedded_server(served: str) -> None:
    async with http_client(served, None) as client:
        await ingested_bags(client)
        await check_search(client, BAGS)


async def test_a_slow_search_becomes_a_job_that_get_job_follows_with_progress(served: str) -> None:
    async with http_client(served, None) as client:
        await ingested_bags(client)
        await check_slow_search_becomes_a_job_with_progress(client, "chatter")


async def test_cancel_job_stops_a_running_search(served: str) -> None:
    async with http_client(served, None) as client:
        await ingested_bags(client)
        await check_cancel_stops_a_running_job(client, "chatter")


def _strip(result: dict[str, Any]) -> dict[str, Any]:
    return {k: v for k, v in result.items() if k != "source"}


@pytest.mark.parametrize(
    "params",
    [
        {"topic": "/odom", "condition": "near_position", "value": {"x": 2, "y": 2, "radius": 0.5}},
        {
            "topic": "/odom",
            "condition": "greater_than",
            "value": 1.0,
            "field": "pose.pose.position.x",
            "correlate_topic": "/cmd_vel",
        },
        {"topic": "/scan", "condition": "less_than", "value": 0.5},
        {"topic": "/cmd_vel", "condition": "between", "value": [0.59, 0.66], "start": 1.0, "end": 8.0},
        {"topic": "/rosout", "condition": "greater_than", "value": 3},
    ],
)
def test_index_and_bag_give_identical_search_results(folder: Path, tmp_path: Path, params: dict[str, Any]) -> None:
    embedded = embedded_resources(folder, tmp_path / "data")
    start_embedded(embedded)
    res = embedded.resources
    wait_until(lambda: all(r.status != "ingesting" for r in res.catalog.all()), timeout_s=120, what="ingest")
    for bag in BAGS:
        request = SearchParams.model_validate({"bag": bag, **params})
        indexed = search_messages(res.access, request, Unreported(), budget_bytes=16_000, use_index=True)
        decoded = search_messages(res.access, request, Unreported(), budget_bytes=16_000, use_index=False)
        assert (indexed.source, decoded.source) == ("index", "bag")
        assert _strip(indexed.model_dump(mode="json")) == _strip(decoded.model_dump(mode="json"))
        assert indexed.total > 0
    embedded.runner.shutdown()


async def test_filter_bag_on_the_embedded_server_stores_the_new_bag_outside_the_folder(
    served: str, folder: Path, tmp_path: Path
) -> None:
    before = sorted(p.name for p in folder.iterdir())
    async with http_client(served, None) as client:
        await ingested_bags(client)
        answer = await finished(
            client,
            await call(
                client, "filter_bag", bag="scenario_db3", include_topics=["/cmd_vel", "/odom"], name="two-topics"
            ),
        )
        expected = {"/cmd_vel": sc.COUNTS["/cmd_vel"], "/odom": sc.COUNTS["/odom"]}
        assert answer["counts"] == expected
        info = await call(client, "bag_info", bag="two-topics")
        assert {t["name"]: t["count"] for t in info["topics"]} == expected
    cli = download_info(served.removesuffix("/mcp"), None, answer["bag_id"], tmp_path)
    assert {t["name"]: t["count"] for t in cli["topics"]} == expected
    assert sorted(p.name for p in folder.iterdir()) == before


def test_bags_made_by_filter_bag_are_listed_again_after_a_restart(folder: Path, tmp_path: Path) -> None:
    first = embedded_resources(folder, tmp_path / "data")
    work = start_embedded(first).work
    res = first.resources
    wait_until(lambda: all(r.status != "ingesting" for r in res.catalog.all()), timeout_s=120, what="ingest")
    params = FilterParams(bag="scenario", include_topics=["/cmd_vel"], name="cmd-only")
    made = filter_bag(res.access, work.store.shelf, work.store.ingestor, params, Unreported())
    first.runner.shutdown()
    again = embedded_resources(folder, tmp_path / "data")
    start_embedded(again)
    catalog = again.resources.catalog
    wait_until(lambda: all(r.status != "ingesting" for r in catalog.all()), timeout_s=120, what="ingest")
    record = catalog.get(made.bag_id)
    assert record is not None
    assert (record.name, record.status) == ("cmd-only", "ready")
    assert record.summary is not None
    assert [t.count for t in record.summary.topics] == [sc.COUNTS["/cmd_vel"]]
    again.runner.shutdown()
