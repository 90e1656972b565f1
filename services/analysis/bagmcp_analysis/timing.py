"""Timing statistics of one topic: rates, periods, jitter, gaps (dropped messages) and header delays.

Period statistics (median, jitter, min/max, gaps) use the positive intervals between the log times sorted
in time order; repeated stamps (period 0) and stamps that go backwards (period < 0, in message order) are
counted separately instead.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt


@dataclass(frozen=True)
class Gap:
    """A silence longer than gap_periods x the median period; index is the last message before it."""

    index: int
    start_ns: int
    end_ns: int
    length_s: float
    periods: float


@dataclass(frozen=True)
class HeaderTiming:
    """Header stamps of the messages that have one; delay = log time - header stamp."""

    present_fraction: float
    rate_hz: float | None
    monotonic: bool
    delay_mean_s: float
    delay_median_s: float
    delay_min_s: float
    delay_max_s: float
    delay_p95_s: float


@dataclass(frozen=True)
class TopicTiming:
    """Timing of one topic; None where fewer than two messages (or distinct stamps) leave it undefined."""

    count: int
    duration_s: float
    rate_hz: float | None
    median_period_s: float | None
    nominal_rate_hz: float | None
    jitter_s: float | None
    jitter_p95_s: float | None
    min_period_s: float | None
    max_period_s: float | None
    gaps: list[Gap]
    gap_count: int
    dropped_estimate: int
    duplicates: int
    out_of_order: int
    header: HeaderTiming | None


@dataclass(frozen=True)
class _PeriodStats:
    median_s: float | None = None
    jitter_s: float | None = None
    jitter_p95_s: float | None = None
    min_s: float | None = None
    max_s: float | None = None


def topic_timing(
    log_ns: npt.NDArray[np.int64],
    header_ns: npt.NDArray[np.int64] | None = None,
    *,
    gap_periods: float = 3.0,
    max_gaps: int = 20,
) -> TopicTiming:
    """Rates, periods, jitter, gaps and header delays of one topic (log_ns in message order).

    header_ns may be None (no header) or hold 0 for messages without a header stamp.
    """
    log = np.asarray(log_ns, dtype=np.int64)
    if log.ndim != 1:
        raise ValueError("log_ns must be a one-dimensional array with one log time per message.")
    if not gap_periods > 1.0:
        raise ValueError("gap_periods must be greater than 1 (a gap is longer than one median period).")
    if max_gaps < 0:
        raise ValueError("max_gaps must be zero or positive.")
    order = np.argsort(log, kind="stable")
    sorted_ns = log[order]
    periods_ns = np.diff(sorted_ns)
    positive_ns = periods_ns[periods_ns > 0]
    stats = _period_stats(positive_ns)
    span_ns = int(sorted_ns[-1] - sorted_ns[0]) if log.size else 0
    gaps = _gaps(sorted_ns, order, stats.median_s, gap_periods)
    message_steps = np.diff(log)
    return TopicTiming(
        count=int(log.size),
        duration_s=span_ns * 1e-9,
        rate_hz=(log.size - 1) / (span_ns * 1e-9) if span_ns > 0 else None,
        median_period_s=stats.median_s,
        nominal_rate_hz=1.0 / stats.median_s if stats.median_s else None,
        jitter_s=stats.jitter_s,
        jitter_p95_s=stats.jitter_p95_s,
        min_period_s=stats.min_s,
        max_period_s=stats.max_s,
        gaps=sorted(gaps, key=lambda gap: (-gap.length_s, gap.index))[:max_gaps],
        gap_count=len(gaps),
        dropped_estimate=sum(math.floor(gap.periods + 0.5) - 1 for gap in gaps),
        duplicates=int((message_steps == 0).sum()),
        out_of_order=int((message_steps < 0).sum()),
        header=None if header_ns is None else header_timing(log, np.asarray(header_ns, dtype=np.int64)),
    )


def _period_stats(positive_ns: npt.NDArray[np.int64]) -> _PeriodStats:
    if positive_ns.size == 0:
        return _PeriodStats()
    periods = positive_ns.astype(np.float64)  # in ns: sums of whole numbers stay exact, so a perfect clock has 0 jitter
    median = float(np.median(periods))
    return _PeriodStats(
        median_s=median * 1e-9,
        jitter_s=float(np.std(periods)) * 1e-9,
        jitter_p95_s=float(np.percentile(np.abs(periods - median), 95.0)) * 1e-9,
        min_s=float(periods.min()) * 1e-9,
        max_s=float(periods.max()) * 1e-9,
    )


def _gaps(
    sorted_ns: npt.NDArray[np.int64], order: npt.NDArray[np.intp], median_s: float | None, gap_periods: float
) -> list[Gap]:
    if median_s is None:
        return []
    periods_ns = np.diff(sorted_ns)
    threshold_ns = gap_periods * median_s * 1e9
    result = []
    for position in np.flatnonzero(periods_ns > threshold_ns).tolist():
        length_s = int(periods_ns[position]) * 1e-9
        result.append(
            Gap(
                index=int(order[position]),
                start_ns=int(sorted_ns[position]),
                end_ns=int(sorted_ns[position + 1]),
                length_s=length_s,
                periods=length_s / median_s,
            )
        )
    return result


def header_timing(log: npt.NDArray[np.int64], header: npt.NDArray[np.int64]) -> HeaderTiming | None:
    """None when no message carries a header stamp (all zero)."""
    if header.shape != log.shape:
        raise ValueError(f"Got {header.size} header stamps for {log.size} log times; pass one of each per message.")
    present = header > 0
    if not present.any():
        return None
    stamps = header[present]
    delays_s = (log[present] - stamps).astype(np.float64) * 1e-9
    span_ns = int(stamps.max() - stamps.min())
    return HeaderTiming(
        present_fraction=float(present.mean()),
        rate_hz=(stamps.size - 1) / (span_ns * 1e-9) if span_ns > 0 else None,
        monotonic=bool((np.diff(stamps) >= 0).all()),
        delay_mean_s=float(delays_s.mean()),
        delay_median_s=float(np.median(delays_s)),
        delay_min_s=float(delays_s.min()),
        delay_max_s=float(delays_s.max()),
        delay_p95_s=float(np.percentile(delays_s, 95.0)),
    )
