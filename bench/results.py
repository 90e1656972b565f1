"""What one benchmark run found, and whether each target was met."""

from __future__ import annotations

from dataclasses import dataclass, field

from bench.bags import BenchBag
from bench.cold import ColdPass
from bench.machine import Machine
from bench.measure import CallResult, LoadResult, Overhead
from bench.profile import Profile
from bench.stats import Timing
from bench.uploads import CacheUse, UploadTiming

GATEWAY_MEDIAN_MS, GATEWAY_P95_MS = 5.0, 10.0
CHEAP_CALLS_PER_S, CHEAP_P99_MS = 200.0, 250.0
THROUGHPUT_CLIENTS = 20


@dataclass
class ModeResult:
    mode: str
    # from start (embedded) or the end of the uploads (stack: each upload waits until ready, so about 0)
    ready_s: float = 0.0
    bags: dict[str, list[CallResult]] = field(default_factory=dict)  # by bag kind
    overhead: list[Overhead] = field(default_factory=list)
    loads: list[LoadResult] = field(default_factory=list)
    profiles: list[Profile] = field(default_factory=list)
    error: str | None = None  # the mode could not be measured to the end


@dataclass
class RunResult:
    machine: Machine
    quick: bool
    repeats: int
    bags: list[BenchBag]
    floors: dict[str, dict[str, Timing]]  # bag kind -> floor key -> timing
    modes: list[ModeResult] = field(default_factory=list)
    wall_s: float = 0.0
    cold: list[ColdPass] = field(default_factory=list)  # the stack's cold passes (bench/cold.py)
    load: list[tuple[str, float]] = field(default_factory=list)  # (phase, 1-minute load average) samples
    uploads: list[UploadTiming] = field(default_factory=list)  # the stack's, each until ready (bench/uploads.py)
    caches: list[tuple[str, list[CacheUse]]] = field(default_factory=list)  # (when, every process's cache)


def cold_limit_ms(result: CallResult, floor: Timing | None) -> float | None:
    """The cold call's limit: a multiple of the floor (plus the tool's warm median where rendering counts)."""
    target = result.call.target
    if target is None or target.cold_floor_factor is None or floor is None:
        return None
    extra = result.warm.median_ms if target.cold_plus_warm else 0.0
    return target.cold_floor_factor * floor.median_ms + extra


def warm_met(result: CallResult) -> bool | None:
    target = result.call.target
    if target is None or target.warm_ms is None:
        return None
    return result.warm.median_ms < target.warm_ms


def cold_met(result: CallResult, floor: Timing | None) -> bool | None:
    limit = cold_limit_ms(result, floor)
    return None if limit is None else result.cold.median_ms < limit


def throughput_met(load: LoadResult) -> bool:
    return load.calls_per_s >= CHEAP_CALLS_PER_S and load.timing.p99_ms < CHEAP_P99_MS and not load.errors


def gateway_met(overhead: Overhead) -> bool:
    return overhead.added_median_ms < GATEWAY_MEDIAN_MS and overhead.added_p95_ms < GATEWAY_P95_MS
