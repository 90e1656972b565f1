"""Timing the calls of one bag cold and warm, the gateway against the service behind it, and many clients."""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import anyio
import psutil

from bench.calls import CALLS, BenchCall
from bench.client import Endpoint, call, timed_call
from bench.stats import Timing
from tests.fixtures.mcp_client import http_client


@dataclass
class CallResult:
    call: BenchCall
    cold: Timing = field(default_factory=Timing)
    warm: Timing = field(default_factory=Timing)


async def bag_durations(endpoint: Endpoint) -> dict[str, tuple[str, float]]:
    """Format -> (name, duration s) of every ready bag, as list_bags shows them."""
    async with http_client(endpoint.url, endpoint.token) as client:
        listed = await call(client, "list_bags", {"limit": 500})
    return {b["format"]: (b["name"], float(b["duration_s"])) for b in listed["bags"] if b["status"] == "ready"}


async def measure_bag(
    endpoint: Endpoint, bag: str, duration_s: float, *, repeats: int, calls: tuple[BenchCall, ...] = CALLS
) -> list[CallResult]:
    """Every call once cold (the first call of that tool on this bag, in the order of ``calls``), then each
    ``repeats`` times warm."""
    results = [CallResult(c) for c in calls]
    async with http_client(endpoint.url, endpoint.token) as client:
        for result in results:
            await timed_call(client, result.call.tool, result.call.arguments(bag, duration_s, 0), result.cold)
        for result in results:
            for rep in range(1, repeats + 1):
                await timed_call(client, result.call.tool, result.call.arguments(bag, duration_s, rep), result.warm)
    return results


@dataclass
class Overhead:
    """One warm call through the gateway and straight to the service behind it, interleaved."""

    label: str
    gateway: Timing = field(default_factory=Timing)
    direct: Timing = field(default_factory=Timing)

    @property
    def added_median_ms(self) -> float:
        return self.gateway.median_ms - self.direct.median_ms

    @property
    def added_p95_ms(self) -> float:
        return self.gateway.p95_ms - self.direct.p95_ms


async def measure_overhead(
    gateway: Endpoint, direct: Endpoint, bag: str, duration_s: float, *, repeats: int
) -> list[Overhead]:
    found = []
    async with http_client(gateway.url, gateway.token) as via, http_client(direct.url, direct.token) as straight:
        for bench_call in (c for c in CALLS if c.cheap):
            overhead = Overhead(bench_call.label)
            for rep in range(repeats + 2):
                arguments = bench_call.arguments(bag, duration_s, rep)
                warmup = rep < 2
                pair = [(via, overhead.gateway), (straight, overhead.direct)]
                # whichever goes first reads the bag's data for these arguments from disk, the second from the
                # page cache: take turns, so neither path is charged for the other's reads
                for client, timing in pair if rep % 2 else pair[::-1]:
                    await timed_call(client, bench_call.tool, arguments, Timing() if warmup else timing)
            found.append(overhead)
    return found


@dataclass
class LoadResult:
    clients: int
    calls_each: int
    wall_s: float = 0.0
    errors: list[str] = field(default_factory=list)
    timing: Timing = field(default_factory=Timing)
    cpu_ms_per_call: dict[str, float] = field(default_factory=dict)  # by process, the bench client included

    @property
    def calls_per_s(self) -> float:
        return len(self.timing) / self.wall_s if self.wall_s else 0.0


BENCH_CLIENT = "bench client"


def _cpu_s(processes: dict[str, psutil.Process]) -> dict[str, float]:
    """CPU seconds (user and system) each process used so far: a server with its children, the bench
    client without them (its children are the servers it started, counted on their own)."""
    found = {}
    for name, process in processes.items():
        family = (process,) if name == BENCH_CLIENT else (process, *process.children(True))
        try:
            found[name] = sum(p.cpu_times().user + p.cpu_times().system for p in family)
        except psutil.Error:
            found[name] = 0.0
    return found


async def run_load(
    endpoint: Endpoint,
    bags: list[tuple[str, float]],
    *,
    clients: int,
    calls_each: int,
    watch: dict[str, int] | None = None,
) -> LoadResult:
    """``clients`` clients, connected and warmed up first (one untimed call of each tool), then all at once
    making ``calls_each`` cheap calls each (bag_info and get_message_at_time in turn, over the bags);
    errors are counted, not raised. The CPU each ``watch``ed process (by pid) and the bench client spent
    per call is recorded, from the start signal to the last client's last answer (not the sessions' close)."""
    load = LoadResult(clients, calls_each)
    watched = {name: psutil.Process(pid) for name, pid in (watch or {}).items()}
    watched[BENCH_CLIENT] = psutil.Process()
    cheap = [c for c in CALLS if c.cheap and c.tool != "list_bags"]
    connected, go, finished = 0, anyio.Event(), [0.0]
    stopped: dict[str, float] = {}

    async def one_client(number: int) -> None:
        nonlocal connected
        async with http_client(endpoint.url, endpoint.token) as client:
            for bench_call in cheap:  # a client's first call of a tool lists the tools and compiles its schema
                name, duration_s = bags[number % len(bags)]
                await call(client, bench_call.tool, bench_call.arguments(name, duration_s, 0))
            connected += 1
            await go.wait()
            for k in range(calls_each):
                bench_call = cheap[(number + k) % len(cheap)]
                name, duration_s = bags[(number + k) % len(bags)]
                try:
                    await timed_call(client, bench_call.tool, bench_call.arguments(name, duration_s, k), load.timing)
                except Exception as err:  # counted: the load test reports errors, never stops
                    load.errors.append(f"{bench_call.tool}: {err}"[:300])
            finished.append(time.perf_counter())
            if len(finished) == clients + 1:  # the last client done: CPU read before the sessions close
                stopped.update(_cpu_s(watched))

    async with anyio.create_task_group() as group:
        for number in range(clients):
            group.start_soon(one_client, number)
        with anyio.fail_after(120):
            while connected < clients:
                await anyio.sleep(0.01)
        before = _cpu_s(watched)
        began = time.perf_counter()
        go.set()
    load.wall_s = max(finished) - began
    after = stopped or _cpu_s(watched)
    calls = max(len(load.timing), 1)
    load.cpu_ms_per_call = {name: 1000 * (after[name] - before[name]) / calls for name in watched}
    return load
