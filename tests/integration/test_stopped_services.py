"""Stopped parts, on real processes (Redis, weed, a bag-store and the gateway; no worker, so a call about a bag
still being ingested waits at the bag-store, its job budget being 60 s here): a call in flight when its service
stops or freezes ends promptly with a sentence naming the service (it waited for the call limit, 600 s by
default), and /readyz says not ready, naming S3, while the S3 server is down (it stayed 200)."""

from __future__ import annotations

import os
import signal
import time
from collections.abc import Iterator
from contextlib import ExitStack
from pathlib import Path

import anyio
import httpx
import pytest

from tests.fixtures.bagfactory import write_chatter_bag
from tests.fixtures.faults import TOKEN, FaultStack, redis_server, weed_server
from tests.fixtures.mcp_client import call, call_error, http_client
from tests.fixtures.processes import HTTP, wait_until
from tests.fixtures.restartable import Restartable
from tests.fixtures.servers import free_ports, remove_weed_sockets

pytestmark = [pytest.mark.integration, pytest.mark.anyio]

CALL_BUDGET_S = 60
# On SIGTERM the bag-store waits for its open requests (a call waiting for an ingest, the gateway's links) for
# the product's stop grace, BAGMCP_STOP_GRACE_S (1 s here, 8 s by default), then closes them and exits; the test
# waits STOP_GRACE_S for that, as a supervisor would (Docker: 10 s), and kills it only past that.
SERVICE_GRACE_S = 1
STOP_GRACE_S = 3


@pytest.fixture(scope="module")
def shared_stack(tmp_path_factory: pytest.TempPathFactory) -> Iterator[FaultStack]:
    """Redis, weed, the bag-store and the gateway, no worker: an uploaded bag stays ingesting. One per module
    (its start took about 15 s of each test's 20-30 s); ``waiting_stack`` hands it on as each test found it."""
    work = tmp_path_factory.mktemp("stopped")
    redis_port, bag_store_port, gateway_port = free_ports(3)
    with ExitStack() as exits:
        redis = redis_server(work, redis_port)
        s3_server, endpoint, sockets = weed_server(work)
        stack = FaultStack(work, endpoint, "stopped", f"redis://127.0.0.1:{redis_port}/0", redis, s3_server)
        exits.callback(remove_weed_sockets, sockets)
        for part in (redis, s3_server):
            exits.callback(part.stop, timeout_s=min(5, part.grace_s))
            part.start()
        service = stack.start_service(
            "bag-store",
            bag_store_port,
            env={"BAGMCP_JOB_BUDGET_S": str(CALL_BUDGET_S), "BAGMCP_STOP_GRACE_S": str(SERVICE_GRACE_S)},
        )
        exits.callback(service.stop, timeout_s=5)
        exits.callback(lambda: stack.gateway.stop(timeout_s=5) if stack.gateway else None)
        stack.start_gateway(gateway_port)
        yield stack


@pytest.fixture
def waiting_stack(shared_stack: FaultStack) -> Iterator[FaultStack]:
    """The shared stack, left as the test found it whatever the test did: a frozen bag-store thawed, a stopped
    part started again, every uploaded bag deleted, and /readyz ready, so the tests pass in any order."""
    yield shared_stack
    bag_store = shared_stack.services["bag-store"]
    if bag_store.process is not None:
        os.kill(bag_store.pid, signal.SIGCONT)
    for part in (shared_stack.s3_server, bag_store):
        if part.process is None:
            part.start()
    readyz = f"{shared_stack.url}/readyz"
    wait_until(lambda: HTTP.get(readyz, timeout=10).status_code == 200, timeout_s=30, what="ready", interval_s=0.05)
    for bag in shared_stack.rest("GET", "bags", params={"limit": 500}).json()["bags"]:
        assert shared_stack.rest("DELETE", f"bags/{bag['id']}").status_code == 204


def _stop(service: Restartable, how: str) -> None:
    time.sleep(2)  # the call is waiting at the bag-store by now
    if how == "frozen":  # SIGSTOP: a host that stopped answering keeps its connections open
        os.kill(service.pid, signal.SIGSTOP)
    else:
        service.stop(sig=signal.SIGTERM, timeout_s=STOP_GRACE_S)


@pytest.mark.parametrize("how", ["stopped", "frozen"])
async def test_a_call_in_flight_when_its_service_stops_ends_promptly_naming_it(
    waiting_stack: FaultStack, tmp_path: Path, how: str
) -> None:
    bag = write_chatter_bag(tmp_path, count=50, name="never_ingested")
    body = next(bag.glob("*.db3")).read_bytes()
    stored = waiting_stack.rest("POST", "bags", params={"filename": "never_ingested.db3"}, content=body)
    assert stored.status_code == 201, stored.text
    bag_store = waiting_stack.services["bag-store"]
    try:
        async with http_client(f"{waiting_stack.url}/mcp", TOKEN) as client:
            began = time.monotonic()
            with anyio.fail_after(CALL_BUDGET_S - 10):  # before the fix: the call limit, 600 s
                async with anyio.create_task_group() as group:
                    group.start_soon(anyio.to_thread.run_sync, _stop, bag_store, how)
                    text = await call_error(client, "bag_info", bag="never_ingested")
            took = time.monotonic() - began
    finally:
        if how == "frozen":
            os.kill(bag_store.pid, signal.SIGCONT)
    assert "bag-store service" in text
    # 2 s before the stop, then at most a poll (1 s) and the fault stack's listing timeout (3 s) with 4 s to spare
    # on a loaded machine (12-13 s with the 10 s default)
    assert took < 10, f"the call took {took:.0f} s: {text}"


async def test_a_call_right_after_its_service_came_back_runs(waiting_stack: FaultStack) -> None:
    """The gateway looks at a service it has down again when a call for one of its tools arrives, instead of
    answering "unavailable right now" until its next look (up to its poll, 5 s by default, after a restart)."""
    readyz = f"{waiting_stack.url}/readyz"
    bag_store = waiting_stack.services["bag-store"]
    bag_store.stop(sig=signal.SIGTERM, timeout_s=STOP_GRACE_S)
    async with http_client(f"{waiting_stack.url}/mcp", TOKEN) as client:
        text = await call_error(client, "list_bags")
        assert "the bag-store service is unavailable right now" in text
        await anyio.to_thread.run_sync(
            lambda: wait_until(
                lambda: HTTP.get(readyz, timeout=10).status_code == 503, timeout_s=30, what="down", interval_s=0.05
            )
        )
        await anyio.to_thread.run_sync(bag_store.start)
        listed = await call(client, "list_bags")
    assert [b["name"] for b in listed["bags"]] == []


def test_readyz_says_not_ready_naming_s3_while_it_is_down(waiting_stack: FaultStack) -> None:
    readyz = f"{waiting_stack.url}/readyz"
    assert httpx.get(readyz, timeout=10).status_code == 200
    waiting_stack.s3_server.stop()
    try:
        wait_until(
            lambda: HTTP.get(readyz, timeout=10).status_code == 503, timeout_s=30, what="not ready", interval_s=0.05
        )
        body = httpx.get(readyz, timeout=10).json()
        assert body["stores_down"] == {"bag-store": ["s3"]}
        assert body["upstreams"]["bag-store"] == "up"
    finally:
        waiting_stack.s3_server.start()
    wait_until(
        lambda: HTTP.get(readyz, timeout=10).status_code == 200, timeout_s=30, what="ready again", interval_s=0.05
    )
