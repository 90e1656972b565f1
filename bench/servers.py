"""The two ways of serving the benchmark measures, as real processes on loopback ports:
``bagmcp serve`` (embedded) and the local stack (redis-server, weed S3, services, workers, gateway)."""

from __future__ import annotations

import subprocess
from collections.abc import Iterator
from contextlib import ExitStack, contextmanager
from dataclasses import dataclass
from pathlib import Path

import anyio

from bench.bags import BenchBag
from bench.client import Endpoint
from bench.uploads import UploadTiming, timed_upload
from tests.fixtures.mcp_client import call, http_client
from tests.fixtures.processes import BIN, http_ok, service
from tests.fixtures.servers import _redis_process, _weed_process, free_port
from tests.integration.stack import SERVICE_TOKEN, TOKEN, Stack, start_stack

INGEST_TIMEOUT_S = 1800.0
JOB_BUDGET_S = "120"  # long enough that every benchmarked call answers with its result


@dataclass(frozen=True)
class Served:
    """One way of serving: the MCP endpoint clients use, the processes to profile, and (stack) the
    bag-store's own endpoint for the gateway comparison."""

    mode: str
    endpoint: Endpoint
    processes: dict[str, subprocess.Popen[bytes]]
    direct: Endpoint | None = None
    running: Stack | None = None  # the stack's processes (for the cold passes' restarts)
    serves: int = 0  # bags it lists once ready (0: the measured ones; embedded serves the whole folder)
    uploads: tuple[UploadTiming, ...] = ()  # the stack: each bag's upload until ready, one after the other


async def wait_ready(endpoint: Endpoint, count: int, *, timeout_s: float = INGEST_TIMEOUT_S) -> None:
    """Until ``count`` bags are listed ready (a failed one stops the benchmark with its reason)."""
    async with http_client(endpoint.url, endpoint.token) as client:
        with anyio.fail_after(timeout_s):
            while True:
                bags = (await call(client, "list_bags", limit=500))["bags"]
                failed = [f"{b['name']}: {b['error']}" for b in bags if b["status"] == "failed"]
                if failed:
                    raise RuntimeError(f"ingest failed: {'; '.join(failed)}")
                if sum(b["status"] == "ready" for b in bags) >= count:
                    return
                await anyio.sleep(0.2)


@contextmanager
def embedded(folder: Path, work: Path) -> Iterator[Served]:
    """``bagmcp serve`` over ``folder`` with a fresh data directory (so ingest runs, and the first calls
    are cold)."""
    port = free_port()
    url = f"http://127.0.0.1:{port}"
    command = [str(BIN / "bagmcp"), "serve", "--bags", str(folder), "--port", str(port), "--data", str(work / "data")]
    env = {"BAGMCP_JOB_BUDGET_S": JOB_BUDGET_S}
    with service("bagmcp-serve", command, env=env, log_dir=work, ready=http_ok(f"{url}/healthz")) as proc:
        count = sum(not p.name.startswith(".") for p in folder.iterdir())
        yield Served("embedded", Endpoint(f"{url}/mcp", None), {"bagmcp serve": proc}, serves=count)


@contextmanager
def stack(bags: list[BenchBag], work: Path, *, extra_bytes: int = 0) -> Iterator[Served]:
    """The local stack with ``bags`` uploaded through the gateway's REST API, each timed until ready before
    the next (room in S3 for ``extra_bytes`` more: the cold passes' warm-up bags)."""
    with ExitStack() as exits:
        redis_url = exits.enter_context(_redis_process())
        volumes = 16 + 2 * (extra_bytes + sum(b.size_bytes for b in bags)) // (64 * 2**20)  # 64 MB each, spare room
        s3 = exits.enter_context(_weed_process(volumes=volumes))
        running = start_stack(redis_url, s3, work, exits, env={"BAGMCP_JOB_BUDGET_S": JOB_BUDGET_S})
        uploads = tuple(timed_upload(running, bag, timeout_s=INGEST_TIMEOUT_S) for bag in bags)
        processes = dict(running.processes)
        processes.update({f"{of} worker": proc for of, proc in running.workers})
        direct = Endpoint(f"{running.bag_store_url}/mcp", SERVICE_TOKEN)
        endpoint = Endpoint(f"{running.url}/mcp", TOKEN)
        yield Served("stack", endpoint, processes, direct, running, uploads=uploads)
