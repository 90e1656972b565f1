"""One benchmark run: bags, floors, then each way of serving measured in turn."""

from __future__ import annotations

import subprocess
import time
from collections.abc import Iterator
from contextlib import ExitStack, contextmanager
from dataclasses import dataclass
from pathlib import Path

from bench.bags import BenchBag
from bench.calls import service_of
from bench.measure import CallResult, bag_durations, measure_bag, run_load
from bench.measure import measure_overhead as gateway_overhead
from bench.profile import MIN_SAMPLES, Profile, recording, summarize
from bench.results import THROUGHPUT_CLIENTS, ModeResult, warm_met
from bench.servers import Served, wait_ready

PROFILE_REPEATS = 40  # enough samples at py-spy's rate for a warm call of ~10 ms


@dataclass(frozen=True)
class Plan:
    repeats: int
    overhead_repeats: int
    loads: tuple[tuple[int, int], ...]  # (clients, calls each)
    profile: bool
    work: Path


@contextmanager
def _profiled(
    processes: dict[str, subprocess.Popen[bytes]], names: list[str], work: Path, label: str
) -> Iterator[list[Profile]]:
    """py-spy on the named processes while the block runs; their summaries fill the yielded list."""
    found: list[Profile] = []
    slug = "".join(c if c.isalnum() else "-" for c in label)[:60]
    outputs = {name: work / f"profile-{slug}-{name.replace(' ', '-')}.txt" for name in names if name in processes}
    with ExitStack() as exits:
        for name, out in outputs.items():
            exits.enter_context(recording(processes[name].pid, out))
        yield found
    summaries = [summarize(out, label=label, process=name) for name, out in outputs.items()]
    found.extend(p for p in summaries if p.samples >= MIN_SAMPLES)


async def measure_mode(served: Served, bags: list[BenchBag], plan: Plan, *, began: float) -> ModeResult:
    mode = ModeResult(served.mode)
    endpoint = served.endpoint
    await wait_ready(endpoint, served.serves or len(bags))
    mode.ready_s = time.monotonic() - began
    listed = await bag_durations(endpoint)
    for bag in bags:
        name, duration_s = listed[bag.kind]
        print(f"[bench] {served.mode}: {bag.kind} ({name})", flush=True)
        mode.bags[bag.kind] = await measure_bag(endpoint, name, duration_s, repeats=plan.repeats)
    named = [listed[b.kind] for b in bags]
    if served.direct is not None:
        print(f"[bench] {served.mode}: gateway vs direct", flush=True)
        mode.overhead = await gateway_overhead(endpoint, served.direct, *named[-1], repeats=plan.overhead_repeats)
    for clients, calls_each in plan.loads:
        print(f"[bench] {served.mode}: {clients} clients x {calls_each} calls", flush=True)
        watch = {name: proc.pid for name, proc in served.processes.items() if not name.endswith("worker")}
        mode.loads.append(await run_load(endpoint, named, clients=clients, calls_each=calls_each, watch=watch))
    if plan.profile:
        mode.profiles = await _profiles(served, named, plan, mode.bags[bags[-1].kind])
    return mode


async def _profiles(
    served: Served, named: list[tuple[str, float]], plan: Plan, last: list[CallResult]
) -> list[Profile]:
    """The cheap calls under load, and every call that missed its warm target on the last bag."""
    found: list[Profile] = []
    serving = ["bagmcp serve"] if served.mode == "embedded" else ["bag-store", "gateway"]
    label = f"{served.mode}: {THROUGHPUT_CLIENTS} clients of cheap calls"
    with _profiled(served.processes, serving, plan.work, label) as profiles:
        await run_load(served.endpoint, named, clients=THROUGHPUT_CLIENTS, calls_each=40)
    found += profiles
    name, duration_s = named[-1]
    for result in last:
        if warm_met(result) is not False:
            continue
        service = service_of(result.call.tool)
        names = ["bagmcp serve"] if served.mode == "embedded" else [service, f"{service} worker"]
        label = f"{served.mode}: {result.call.label} (warm, x{PROFILE_REPEATS})"
        with _profiled(served.processes, names, plan.work, label) as profiles:
            await measure_bag(served.endpoint, name, duration_s, repeats=PROFILE_REPEATS, calls=(result.call,))
        found += profiles
    return found
