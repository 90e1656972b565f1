"""Latency samples and what the report says about them: median, p95, p99, throughput."""

from __future__ import annotations

import time
from collections.abc import Awaitable, Callable
from dataclasses import dataclass, field
from typing import TypeVar

import numpy as np

T = TypeVar("T")


@dataclass
class Timing:
    """Wall-clock durations of repeated runs of one piece of work, in milliseconds."""

    samples_ms: list[float] = field(default_factory=list)

    def add_s(self, seconds: float) -> None:
        self.samples_ms.append(seconds * 1000.0)

    def percentile(self, q: float) -> float:
        return float(np.percentile(self.samples_ms, q)) if self.samples_ms else float("nan")

    @property
    def median_ms(self) -> float:
        return self.percentile(50)

    @property
    def p95_ms(self) -> float:
        return self.percentile(95)

    @property
    def p99_ms(self) -> float:
        return self.percentile(99)

    def __len__(self) -> int:
        return len(self.samples_ms)


def timed(run: Callable[[], T], timing: Timing) -> T:
    began = time.perf_counter()
    result = run()
    timing.add_s(time.perf_counter() - began)
    return result


async def timed_async(run: Callable[[], Awaitable[T]], timing: Timing) -> T:
    began = time.perf_counter()
    result = await run()
    timing.add_s(time.perf_counter() - began)
    return result


def repeat(run: Callable[[], object], times: int) -> Timing:
    """``run`` timed ``times`` times in a row."""
    timing = Timing()
    for _ in range(times):
        timed(run, timing)
    return timing
