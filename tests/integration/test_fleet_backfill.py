"""Views added on start: a ready bag whose index lost its views' files (as an index made before they existed)
gets them back when ``bagmcp serve`` starts again over the same data directory, and its rows answer again."""

from __future__ import annotations

from pathlib import Path

import anyio
import pytest

from bagmcp_bag_store.fleet.files import file_name
from tests.checks.fleet_checks import query
from tests.fixtures.bagfactory import BagKind
from tests.fixtures.drive_bags import expected_topic_counts
from tests.fixtures.drive_logs import LOGS
from tests.fixtures.inprocess import copy_bags, in_process
from tests.fixtures.mcp_client import http_client
from tests.fixtures.processes import BIN, http_ok, service
from tests.fixtures.servers import free_port

TOKEN = "backfill-admin-token"
WRITTEN = ["bags", "topics", "poses", "twists", "imu", "gps", "scans", "logs", "tf_edges"]  # no battery
COUNTS = "SELECT (SELECT count(*) FROM poses), (SELECT count(*) FROM scans), (SELECT count(*) FROM logs)"


def _views(data: Path) -> list[str]:
    return sorted(p.name for p in data.rglob("fleet.*"))


async def _counts(url: str) -> tuple[list[list[object]], list[str]]:
    async with http_client(f"{url}/mcp", TOKEN) as client:
        with anyio.fail_after(60):
            while (await query(client, "SELECT count(*) FROM bags"))["rows"] != [[1]]:
                await anyio.sleep(0.2)
        answer = await query(client, COUNTS)
    return answer["rows"], answer["missing_bags"]


def test_a_restart_adds_the_views_a_ready_bags_index_lacks(
    drive_bags: dict[BagKind, Path], tmp_path_factory: pytest.TempPathFactory
) -> None:
    folder = copy_bags([drive_bags["ros2-mcap"]], tmp_path_factory.mktemp("backfill") / "bags")
    data = tmp_path_factory.mktemp("backfill-data")
    with in_process(folder, data) as first:  # the first start: ingest writes the views into the index
        record = first.composition.embedded.resources.catalog.named("drive_mcap")
        assert record is not None
        assert record.status == "ready"
    assert _views(data) == sorted(map(file_name, WRITTEN))
    for path in data.rglob("fleet.*"):
        path.unlink()
    assert _views(data) == []

    port = free_port()
    url = f"http://127.0.0.1:{port}"
    command = [str(BIN / "bagmcp"), "serve", "--bags", str(folder), "--port", str(port), "--token", TOKEN]
    logs = tmp_path_factory.mktemp("backfill-logs")
    with service(
        "fleet-backfill", [*command, "--data", str(data)], env={}, log_dir=logs, ready=http_ok(f"{url}/healthz")
    ):
        rows, missing = anyio.run(_counts, url)
    counts = expected_topic_counts("ros2-mcap")
    assert rows == [[counts["/odom"], counts["/scan"], len(LOGS)]]
    assert missing == []
    assert _views(data) == sorted(map(file_name, WRITTEN))
