"""Per-row numbers the views add to what the index holds: each pose's speed, each topic's longest gap."""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

from bagmcp_shared.index import ColumnIndex
from bagmcp_shared.timebase import MAX_CLOCK_SKEW_NS

MIN_WINDOW_NS = 50_000_000
Floats = npt.NDArray[np.float64]


def _clock(t_ns: npt.NDArray[np.int64], header_ns: npt.NDArray[np.int64]) -> npt.NDArray[np.int64]:
    """Header stamps when every one is set, they never go backwards and they are on the log's clock (the rule
    analyze_trajectory follows), else log times."""
    if len(header_ns) < 2 or (header_ns <= 0).any() or (np.diff(header_ns) < 0).any():
        return t_ns
    return header_ns if float(np.median(np.abs(header_ns - t_ns))) <= MAX_CLOCK_SKEW_NS else t_ns


def pose_speeds(t_ns: npt.NDArray[np.int64], header_ns: npt.NDArray[np.int64], x: Floats, y: Floats) -> Floats:
    """Each pose's 2D speed (m/s): the straight-line distance to the first pose at least one window later, over
    the time between them. The window is max(0.05 s, 2 x the median step), as analyze_trajectory's, so batched
    stamps give no absurd speeds and the largest of these is at least analyze_trajectory's max_speed_mps (its
    windows start at some of these poses). Poses within one window of the end take the last full window's
    speed; NaN when the stamps never advance."""
    count = len(t_ns)
    speeds = np.full(count, np.nan)
    mono = np.maximum.accumulate(_clock(t_ns, header_ns)) if count else t_ns
    steps = np.diff(mono)
    positive = steps[steps > 0]
    if positive.size == 0:
        return speeds
    window_ns = max(MIN_WINDOW_NS, math.ceil(2.0 * float(np.median(positive))))
    ends = np.searchsorted(mono, mono + window_ns, side="left")
    full = ends < count
    if not full.any():  # shorter than one window: measure over everything
        elapsed = (mono[-1] - mono[0]) * 1e-9
        return np.full(count, math.hypot(x[-1] - x[0], y[-1] - y[0]) / elapsed)
    starts = np.flatnonzero(full)
    stop = ends[starts]
    speeds[starts] = np.hypot(x[stop] - x[starts], y[stop] - y[starts]) / ((mono[stop] - mono[starts]) * 1e-9)
    speeds[starts[-1] + 1 :] = speeds[starts[-1]]
    return speeds


def _times(index: ColumnIndex, topic: str) -> npt.NDArray[np.int64] | None:
    if index.columns(topic):
        return index.read(topic, []).t_ns
    records = index.logs(topic) if topic in index.log_topics() else None
    return np.asarray([r.t_ns for r in records], dtype=np.int64) if records else None


def topic_gap(index: ColumnIndex, topic: str) -> tuple[float, int] | None:
    """The longest time between consecutive messages of ``topic`` (log time, s) and the stamp (ns) it
    starts at; None when the index does not hold the topic's message times (images, point clouds, TF) or
    it has fewer than two messages."""
    times = _times(index, topic)
    if times is None or len(times) < 2:
        return None
    ordered = np.sort(times)
    steps = np.diff(ordered)
    where = int(np.argmax(steps))
    return float(steps[where]) / 1e9, int(ordered[where])
