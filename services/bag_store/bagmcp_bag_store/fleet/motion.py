"""Per-row numbers the views add to what the index holds: each pose's speed, each topic's longest gap."""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

from bagmcp_shared.index import ColumnIndex

MIN_WINDOW_NS = 50_000_000
MAX_RATE_RATIO = 20.0
Floats = npt.NDArray[np.float64]


def _clock(t_ns: npt.NDArray[np.int64], header_ns: npt.NDArray[np.int64]) -> tuple[npt.NDArray[np.int64], bool]:
    """(stamps, on log time): header stamps when every one is set, they never go backwards and they advance with
    log time (at a rate within MAX_RATE_RATIO of it: a simulation's clock counts), else log times. The rule of
    analyze_trajectory (analysis/queries/poses.py, pose_clock), kept in step with it."""
    if len(header_ns) < 2 or (header_ns <= 0).any() or (np.diff(header_ns) < 0).any():
        return t_ns, True
    log_span, header_span = int(t_ns.max() - t_ns.min()), int(header_ns[-1] - header_ns[0])
    if header_span <= 0 or (log_span > 0 and not 1 / MAX_RATE_RATIO <= header_span / log_span <= MAX_RATE_RATIO):
        return t_ns, True
    return header_ns, False


def pose_speeds(t_ns: npt.NDArray[np.int64], header_ns: npt.NDArray[np.int64], x: Floats, y: Floats) -> Floats:
    """Each pose's 2D speed (m/s): the straight-line distance to the first pose at least one window later, over
    the time between them. The window is max(0.05 s, 2 x the median step), as analyze_trajectory's, so batched
    stamps give no absurd speeds; on log time a window's time is at least its steps x the median step (a
    recorder's stall and burst is no speed peak), also as analyze_trajectory's. The largest of these speeds
    is at least analyze_trajectory's max_speed_mps (its windows start at some of these poses). Poses within
    one window of the end take the last full window's speed; NaN when the stamps never advance."""
    count = len(t_ns)
    speeds = np.full(count, np.nan)
    stamps, log_time = _clock(t_ns, header_ns) if count else (t_ns, True)
    mono = np.maximum.accumulate(stamps) if count else t_ns
    steps = np.diff(mono)
    positive = steps[steps > 0]
    if positive.size == 0:
        return speeds
    median_ns = float(np.median(positive))
    window_ns = max(MIN_WINDOW_NS, math.ceil(2.0 * median_ns))
    ends = np.searchsorted(mono, mono + window_ns, side="left")
    full = ends < count
    if not full.any():  # shorter than one window: measure over everything
        elapsed = (mono[-1] - mono[0]) * 1e-9
        return np.full(count, math.hypot(x[-1] - x[0], y[-1] - y[0]) / elapsed)
    starts = np.flatnonzero(full)
    stop = ends[starts]
    elapsed_s = (mono[stop] - mono[starts]) * 1e-9
    if log_time:
        elapsed_s = np.maximum(elapsed_s, (stop - starts) * median_ns * 1e-9)
    speeds[starts] = np.hypot(x[stop] - x[starts], y[stop] - y[starts]) / elapsed_s
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
