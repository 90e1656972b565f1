"""The cold passes on a running stack, in order: cold (per tool, fresh processes), cold with 20 ms per S3
request, and a block cache a quarter of the bag. The warm-up bags are uploaded first."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from functools import partial
from pathlib import Path

import anyio

from bench.bags import BenchBag
from bench.calls import CALLS
from bench.client import Endpoint, call
from bench.cold import COLD_REP, DELAYED_REP, Answers, ColdPass, ColdSetup, per_tool_pass, quarter_pass
from bench.delay_proxy import delay_proxy
from bench.machine import LoadWatch
from bench.restarts import FreshServices
from bench.servers import INGEST_TIMEOUT_S, Served
from tests.fixtures.mcp_client import http_client

S3_DELAY_MS = 20.0
WARMUP = "warmup-"
QUARTER_BLOCK = {"BAGMCP_BLOCK_BYTES": str(2**20), "BAGMCP_READ_AHEAD_BYTES": str(8 * 2**20)}
QUICK_QUARTER_BLOCK = {"BAGMCP_BLOCK_BYTES": str(64 * 2**10), "BAGMCP_READ_AHEAD_BYTES": str(512 * 2**10)}
MIN_BLOCKS_OF_BOUND = 4  # the services refuse a bound under 4 x (block + read-ahead)


@dataclass(frozen=True)
class ColdPlan:
    repeats: int  # warm calls after each cold one
    delayed_repeats: int
    passes: tuple[str, ...]  # of "cold", "delayed", "quarter"
    work: Path
    only: tuple[str, ...] = ()  # calls whose label holds one of these (all when empty)
    watch: LoadWatch | None = None  # told each pass as its phase
    on_pass: Callable[[list[ColdPass]], None] | None = None  # the passes so far, after each one (saved)
    profile: bool = False  # py-spy on the answering service and worker during each first call


def quarter_env(bags: list[BenchBag]) -> tuple[int, dict[str, str]]:
    """The bound (a quarter of the smallest bag) and the settings of the quarter pass: the block cache and
    the whole-copy cache both bounded by it, blocks small enough that the services accept the bound."""
    bound = min(b.size_bytes for b in bags) // 4
    full = 4 * (int(QUARTER_BLOCK["BAGMCP_BLOCK_BYTES"]) + int(QUARTER_BLOCK["BAGMCP_READ_AHEAD_BYTES"]))
    blocks = QUARTER_BLOCK if bound >= full else QUICK_QUARTER_BLOCK
    return bound, {**blocks, "BAGMCP_BLOCK_CACHE_BYTES": str(bound), "BAGMCP_CACHE_MAX_BYTES": str(bound)}


def _phase(plan: ColdPlan, name: str) -> None:
    if plan.watch is not None:
        plan.watch.phase = name


def _done(plan: ColdPlan, found: list[ColdPass]) -> None:
    if plan.on_pass is not None:
        plan.on_pass(list(found))


async def _ready(endpoint: Endpoint, names: list[str]) -> dict[str, tuple[str, float]]:
    """Name -> (name, duration s) of every ready bag, once all of ``names`` are ready (the stack lists
    filter_bag's outputs too, so a count would not do)."""
    async with http_client(endpoint.url, endpoint.token) as client:
        with anyio.fail_after(INGEST_TIMEOUT_S):
            while True:
                bags = (await call(client, "list_bags", {"limit": 500}))["bags"]
                failed = [f"{b['name']}: {b['error']}" for b in bags if b["name"] in names and b["status"] == "failed"]
                if failed:
                    raise RuntimeError(f"ingest failed: {'; '.join(failed)}")
                ready = {b["name"]: (b["name"], float(b["duration_s"])) for b in bags if b["status"] == "ready"}
                if all(name in ready for name in names):
                    return ready
                await anyio.sleep(0.3)


async def measure_cold(served: Served, bags: list[BenchBag], warmups: list[BenchBag], plan: ColdPlan) -> list[ColdPass]:
    running = served.running
    if running is None:
        raise RuntimeError("the cold passes need the local stack")
    for bag in warmups:
        await anyio.to_thread.run_sync(partial(running.upload_ok, bag.path, name=WARMUP + bag.name))
    listed = await _ready(served.endpoint, [b.name for b in bags] + [WARMUP + b.name for b in warmups])
    setup_bags: dict[str, tuple[str, float]] = {b.kind: listed[b.name] for b in bags}
    warm: dict[str, tuple[str, float]] = {b.kind: listed[WARMUP + b.name] for b in warmups}
    fresh = FreshServices(running, plan.work)
    found: list[ColdPass] = []
    answers: Answers = {}
    try:
        with delay_proxy(running.s3.endpoint) as proxy:
            calls = tuple(c for c in CALLS if not plan.only or any(part in c.label for part in plan.only))
            profiles = plan.work / "cold-profiles" if plan.profile else None
            if profiles is not None:
                profiles.mkdir(exist_ok=True)
            setup = ColdSetup(served.endpoint, fresh, proxy, setup_bags, warm, calls, profiles)
            _phase(plan, "stack cold")
            if "cold" in plan.passes or "quarter" in plan.passes:  # the quarter pass checks against its answers
                cold = per_tool_pass(setup, "cold", delay_ms=0.0, repeats=plan.repeats, rep=COLD_REP, answers=answers)
                found.append(await cold)
                _done(plan, found)
            if "delayed" in plan.passes:
                _phase(plan, "stack cold, 20 ms per S3 request")
                delayed = per_tool_pass(
                    setup, "delayed", delay_ms=S3_DELAY_MS, repeats=plan.delayed_repeats, rep=DELAYED_REP, answers={}
                )
                found.append(await delayed)
                _done(plan, found)
            if "quarter" in plan.passes:
                _phase(plan, "stack, quarter cache")
                bound, env = quarter_env(bags)
                found.append(
                    await quarter_pass(setup, cache_bytes=bound, env=env, repeats=plan.delayed_repeats, answers=answers)
                )
                _done(plan, found)
    finally:
        await anyio.to_thread.run_sync(fresh.close)
    return found
