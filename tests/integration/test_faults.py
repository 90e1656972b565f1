"""Fault tests on real processes (tests/fixtures/faults.py): workers killed outright (the main process or a
pool child) mid-ingest and mid-filter, Redis, the S3 server and the bag-store stopped under calls, an upload
cut half way. Each ends with every bag ready or failed with a reason within a stated time, nothing lost,
nothing duplicated, no orphan objects and no temporary files (tests/checks/fault_checks.py).

Times stated here hold with the test stack's visibility timeout of 2 s (60 s by default, see the README):
a task of a worker that died goes to another worker within that plus one restore sweep (1 s here).
"""

from __future__ import annotations

import re
import subprocess
import time
from collections.abc import Iterator
from contextlib import ExitStack
from pathlib import Path

import anyio
import httpx
import pytest

from bagmcp_bag_store.task_refs import INGEST
from tests.checks.fault_checks import check_consistent
from tests.checks.search_checks import finished
from tests.fixtures.bagfactory import BagKind
from tests.fixtures.faults import (
    PREFORK,
    TOKEN,
    VISIBILITY_TIMEOUT_S,
    FaultStack,
    cut_upload,
    settle,
    start_fault_stack,
)
from tests.fixtures.heavy_bags import write_odometry_bag
from tests.fixtures.mcp_client import call, call_error, http_client
from tests.fixtures.processes import BIN, HTTP, wait_until
from tests.fixtures.restartable import Restartable

pytestmark = pytest.mark.anyio
HEAVY_MESSAGES = 150_000  # about 8 s of ingest on a loaded 2-core machine
# The long ingest must outlast two visibility timeouts (4 s): 200,000 take about 8 s alone on this 2-core machine
# (300,000 took 12.3 s alone and 40 s beside the rest of the suite, when the timeout was 3 s)
LONG_MESSAGES = 200_000
SETTLE_S = 60  # the bound every test states: the bag is ready or failed with a reason within this
# ... except the long ingest, long on purpose: sized to outlast two visibility timeouts on a fast machine, it took
# over 60 s on a 2 GHz first-generation Zen beside the rest of the suite (2026-11-28)
LONG_SETTLE_S = 240


@pytest.fixture(scope="module")
def faults(tmp_path_factory: pytest.TempPathFactory) -> Iterator[FaultStack]:
    with ExitStack() as exits:
        yield start_fault_stack(tmp_path_factory.mktemp("faults"), exits)


def _upload(stack: FaultStack, path: Path) -> str:
    command = [str(BIN / "bagmcp"), "upload", str(path), "--url", stack.url, "--token", TOKEN]
    result = subprocess.run(command, capture_output=True, text=True, timeout=300, check=False)
    assert result.returncode == 0, result.stderr
    return result.stdout.split()[0]


def _ingesting_with_progress(stack: FaultStack, bag_id: str) -> None:
    def started() -> bool:
        record = stack.rest("GET", f"bags/{bag_id}").json()
        assert record["status"] == "ingesting", record
        return (record["progress"] or 0) > 0.02

    wait_until(started, timeout_s=60, what="ingest to be under way", interval_s=0.05)


def _received(workers: list[Restartable], since: dict[str, int], task: str) -> int:
    """How many times ``task`` was handed to one of ``workers`` after the log offsets ``since``."""
    pattern = re.compile(rf"Task {re.escape(task)}\[[0-9a-f-]+\] received")
    return sum(len(pattern.findall(w.log.read_text(errors="replace")[since.get(w.name, 0) :])) for w in workers)


def _offsets(workers: list[Restartable]) -> dict[str, int]:
    return {w.name: len(w.log.read_text(errors="replace")) if w.log.exists() else 0 for w in workers}


def test_a_worker_killed_outright_mid_ingest_is_restarted_and_the_bag_ends_ready(
    faults: FaultStack, tmp_path: Path
) -> None:
    worker = faults.workers[0]
    since = _offsets([worker])
    bag_id = _upload(faults, write_odometry_bag(tmp_path, count=HEAVY_MESSAGES, name="odom_main_killed"))
    _ingesting_with_progress(faults, bag_id)
    worker.kill()  # SIGKILL of the main process of a solo worker: the task dies with it, unacknowledged
    killed_at = time.monotonic()
    worker.restart()  # as make stack's supervisor, systemd or a compose restart policy would
    settled = settle(faults, timeout_s=SETTLE_S)
    assert settled.bags["odom_main_killed"] == ("ready", None)
    assert time.monotonic() - killed_at < SETTLE_S
    assert _received([worker], since, INGEST.name) == 2  # the killed run and the one redelivery
    check_consistent(faults)


def test_a_live_worker_keeps_a_long_ingest_to_itself(faults: FaultStack, tmp_path: Path) -> None:
    other = faults.start_worker(name="bag-store-worker-idle")
    workers = [faults.workers[0], other]
    since = _offsets(workers)
    try:
        _upload(faults, write_odometry_bag(tmp_path, count=LONG_MESSAGES, name="odom_long"))
        assert settle(faults, timeout_s=LONG_SETTLE_S).bags["odom_long"] == ("ready", None)
    finally:
        other.stop()
        faults.workers.remove(other)
    logs = "".join(w.log.read_text(errors="replace")[since[w.name] :] for w in workers)
    took = [float(s) for s in re.findall(rf"Task {re.escape(INGEST.name)}\[[0-9a-f-]+\] succeeded in ([\d.]+)s", logs)]
    assert len(took) == 1
    assert took[0] > 2 * VISIBILITY_TIMEOUT_S, "the ingest was too quick to show that it is not handed out again"
    assert _received(workers, since, INGEST.name) == 1  # never given to the idle worker meanwhile
    check_consistent(faults)


async def test_a_pool_child_killed_mid_ingest_and_mid_filter_is_replaced_and_the_work_completes(
    faults: FaultStack, tmp_path: Path
) -> None:
    solo = faults.workers[0]
    solo.stop()
    prefork = faults.start_worker(pool=PREFORK, name="bag-store-prefork")
    main_pid = prefork.pid
    try:
        bag_id = _upload(faults, write_odometry_bag(tmp_path, count=HEAVY_MESSAGES, name="odom_child_killed"))
        _ingesting_with_progress(faults, bag_id)
        prefork.kill_child()  # the main process sees its child die and puts the task back at once
        settled = settle(faults, timeout_s=SETTLE_S)
        assert settled.bags["odom_child_killed"] == ("ready", None)
        async with http_client(f"{faults.url}/mcp", TOKEN) as client:
            answer = await call(client, "filter_bag", bag="odom_child_killed", end=600.0, name="odom_child_half")
            job_id = answer["job"]["job_id"]
            with anyio.fail_after(60):
                while (await call(client, "get_job", job_id=job_id))["progress"] <= 0.05:
                    await anyio.sleep(0.05)
            prefork.kill_child()
            result = await finished(client, answer, timeout_s=SETTLE_S)
            listed = await call(client, "list_bags", name="odom_child_half")
        assert result["counts"] == {"/odom": 60_001}  # 0 s to 600 s at 100 Hz, both ends included
        assert [(b["name"], b["status"], b["message_count"]) for b in listed["bags"]] == [
            ("odom_child_half", "ready", 60_001)
        ]
        assert prefork.pid == main_pid
        check_consistent(faults)
    finally:
        prefork.stop()
        faults.workers.remove(prefork)
        solo.start()


async def test_redis_stopped_under_calls_gives_clear_errors_and_everything_recovers_without_restarts(
    faults: FaultStack, tmp_path: Path
) -> None:
    before = {b["name"] for b in faults.rest("GET", "bags", params={"limit": 500}).json()["bags"]}
    small = write_odometry_bag(tmp_path, count=100, name="odom_during_redis_outage")
    faults.redis.stop(timeout_s=5)
    try:
        ready = httpx.get(f"{faults.url}/readyz", timeout=30)
        assert ready.status_code == 503
        assert ready.json()["redis"] == "down"
        async with http_client(f"{faults.url}/mcp", TOKEN) as client:
            assert "(Redis) is unreachable" in await call_error(client, "list_bags")
        assert "Redis" in _upload_refused(faults, small)
    finally:
        faults.redis.start()
    wait_until(lambda: HTTP.get(f"{faults.url}/readyz").status_code == 200, timeout_s=30, what="ready again")
    async with http_client(f"{faults.url}/mcp", TOKEN) as client:
        assert {b["name"] for b in (await call(client, "list_bags", limit=500))["bags"]} == before
    _upload(faults, small)
    assert settle(faults, timeout_s=SETTLE_S).bags["odom_during_redis_outage"] == ("ready", None)
    check_consistent(faults)


def _upload_refused(stack: FaultStack, path: Path) -> str:
    command = [str(BIN / "bagmcp"), "upload", str(path), "--url", stack.url, "--token", TOKEN]
    refused = subprocess.run(command, capture_output=True, text=True, timeout=120, check=False)
    assert refused.returncode == 1
    assert "Traceback" not in refused.stderr
    return refused.stderr


async def test_the_s3_server_stopped_under_calls_gives_clear_errors_and_everything_recovers(
    faults: FaultStack, tmp_path: Path
) -> None:
    small = write_odometry_bag(tmp_path, count=100, name="odom_during_s3_outage")
    objects, listed = faults.objects(), faults.rest("GET", "bags", params={"limit": 500}).json()["total"]
    faults.s3_server.stop(timeout_s=3)
    try:
        refused = _upload_refused(faults, small)
        assert "503" in refused
        assert "object store" in refused
        async with http_client(f"{faults.url}/mcp", TOKEN) as client:
            assert (await call(client, "list_bags", limit=500))["total"] == listed  # the catalog lives in Redis
    finally:
        faults.s3_server.start()
    assert faults.objects() == objects
    _upload(faults, small)
    assert settle(faults, timeout_s=SETTLE_S).bags["odom_during_s3_outage"] == ("ready", None)
    check_consistent(faults)


def test_the_bag_store_killed_mid_upload_comes_back_clean_and_the_gateway_follows(
    faults: FaultStack, tmp_path: Path
) -> None:
    bag = write_odometry_bag(tmp_path, count=20_000, name="odom_bag_store_killed")
    data = b"".join(p.read_bytes() for p in sorted(bag.iterdir()) if p.suffix == ".db3")
    objects, bag_store = faults.objects(), faults.services["bag-store"]

    def slow_body() -> Iterator[bytes]:
        for at in range(0, len(data), 1 << 20):
            if at == 4 << 20:
                bag_store.kill()  # mid-body, with the first megabytes already in its scratch directory
            yield data[at : at + (1 << 20)]

    try:
        answer = faults.rest("POST", "bags", params={"filename": "cut.db3"}, content=slow_body())
    except httpx.HTTPError:
        pass  # the connection broke
    else:
        assert answer.status_code == 503, answer.text  # the gateway says the bag-store went away
    bag_store.restart()
    wait_until(lambda: HTTP.get(f"{faults.url}/readyz").status_code == 200, timeout_s=30, what="the gateway")
    assert faults.objects() == objects
    _upload(faults, bag)
    assert settle(faults, timeout_s=SETTLE_S).bags["odom_bag_store_killed"] == ("ready", None)
    check_consistent(faults)


def test_an_upload_cut_half_way_leaves_nothing_and_the_same_bag_uploads_whole_after(
    faults: FaultStack, scenario_bags: dict[BagKind, Path]
) -> None:
    objects, listed = faults.objects(), faults.rest("GET", "bags", params={"limit": 500}).json()["total"]
    cut_upload(faults, scenario_bags["ros1"], fraction=0.5)
    assert faults.objects() == objects
    assert faults.rest("GET", "bags", params={"limit": 500}).json()["total"] == listed
    check_consistent(faults)  # no half body left in the bag-store's scratch
    whole = faults.rest("POST", "bags", params={"filename": "scenario.bag"}, content=scenario_bags["ros1"].read_bytes())
    assert whole.status_code == 201
    assert settle(faults, timeout_s=SETTLE_S).bags["scenario"] == ("ready", None)
    check_consistent(faults)
