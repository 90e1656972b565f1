"""Windowed motion of a track: speeds robust to batched stamps, moving/stopped time, stops, stationary runs.

Speeds are the 2D straight-line displacement over windows of elapsed time of at least
max(0.05 s, 2 x median positive step), so messages that share (nearly) one log time cannot produce absurd
speeds. Windows start at a sample and end at the first sample at least one window later; the short remainder
at the end of the track counts towards the time of the last window but not towards its speed (its poses may
share one stamp). Stamps that go backwards are replaced by the running maximum (they add no elapsed time).

On log time (a track without usable header stamps) a window's time base is at least its number of steps x the
median step: a recorder that stalls for 0.235 s and then writes the stalled messages in a burst would otherwise
put 0.235 s of motion into a few milliseconds (the nav2 TurtleBot's 1.5 m/s "peak" of a robot capped at 0.5).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from bagmcp_analysis.trajectory.types import Stop, Track

MIN_WINDOW_NS = 50_000_000
MIN_STOP_S = 0.5
NEAR_REPEAT_DIVISOR = 100  # steps up to 1 % of the speed window count as repeated stamps


@dataclass(frozen=True)
class StationaryRun:
    """Consecutive windows in which the position barely changes (the heading may change)."""

    start_index: int
    end_index: int
    turn_rad: float | None


@dataclass(frozen=True, eq=False)
class Motion:
    """Per-window measurements; `span_ends` and `elapsed_s` include the short remainder at the end."""

    window_s: float | None
    starts: npt.NDArray[np.int64]
    span_ends: npt.NDArray[np.int64]
    elapsed_s: npt.NDArray[np.float64]
    speed_mps: npt.NDArray[np.float64]
    moving: npt.NDArray[np.bool_]
    stops: list[Stop]
    stationary: list[StationaryRun]
    repeated_stamps: int  # steps of at most 1 % of the window (exact or near repeats)
    backwards_stamps: int
    bursts: int = 0  # windows on log time whose time base was their message count (see module doc)

    @property
    def duration_s(self) -> float:
        return float(self.elapsed_s.sum())


def analyse_motion(track: Track, *, stop_speed_mps: float, turn_rate_rps: float) -> Motion:
    """Split the track into time windows and classify each as moving or stopped."""
    mono_ns = np.maximum.accumulate(track.t_ns) if track.t_ns.size else track.t_ns
    window_ns = _window_length_ns(mono_ns)
    repeated, backwards = _stamp_anomalies(track.t_ns, window_ns)
    bounds = _window_bounds(mono_ns, window_ns)
    starts, ends = bounds[:-1], bounds[1:]
    span_ends = ends.copy()
    if span_ends.size:
        span_ends[-1] = track.t_ns.size - 1
    elapsed_s = (mono_ns[span_ends] - mono_ns[starts]).astype(np.float64) * 1e-9
    raw_s = (mono_ns[ends] - mono_ns[starts]).astype(np.float64) * 1e-9
    measured_s = _time_base_s(track, mono_ns, starts, ends, raw_s)
    chord_m = np.hypot(track.x[ends] - track.x[starts], track.y[ends] - track.y[starts])
    speed = chord_m / measured_s if starts.size else np.zeros(0)
    unwrapped = _unwrapped_yaw(track.yaw)
    turn_rad = unwrapped[span_ends] - unwrapped[starts]
    turn_rate = np.abs(turn_rad) / np.where(elapsed_s > 0, elapsed_s, np.inf)
    turning = np.nan_to_num(turn_rate, nan=0.0) > turn_rate_rps
    stationary_mask = speed <= stop_speed_mps
    moving = ~stationary_mask | turning
    return Motion(
        window_s=None if window_ns is None else window_ns * 1e-9,
        starts=starts,
        span_ends=span_ends,
        elapsed_s=elapsed_s,
        speed_mps=speed,
        moving=moving,
        stops=_stops(_sample_runs(~moving, starts, span_ends), elapsed_s),
        stationary=_stationary_runs(_sample_runs(stationary_mask, starts, span_ends), unwrapped),
        repeated_stamps=repeated,
        backwards_stamps=backwards,
        bursts=int((measured_s > raw_s + 1e-9).sum()),
    )


def _time_base_s(
    track: Track,
    mono_ns: npt.NDArray[np.int64],
    starts: npt.NDArray[np.int64],
    ends: npt.NDArray[np.int64],
    elapsed: npt.NDArray[np.float64],
) -> npt.NDArray[np.float64]:
    """Seconds each window's speed divides by: its elapsed time, and on log time at least steps x median step."""
    steps = np.diff(mono_ns)
    positive = steps[steps > 0]
    if not track.log_time or positive.size == 0:
        return elapsed
    median_s = float(np.median(positive)) * 1e-9
    return np.maximum(elapsed, (ends - starts).astype(np.float64) * median_s)


def _stamp_anomalies(t_ns: npt.NDArray[np.int64], window_ns: int | None) -> tuple[int, int]:
    """(repeated, backwards) steps; a step of at most 1 % of the speed window counts as a repeat."""
    steps = np.diff(t_ns)
    near_ns = 0 if window_ns is None else window_ns // NEAR_REPEAT_DIVISOR
    return int(((steps >= 0) & (steps <= near_ns)).sum()), int((steps < 0).sum())


def _window_length_ns(mono_ns: npt.NDArray[np.int64]) -> int | None:
    steps = np.diff(mono_ns)
    positive = steps[steps > 0]
    if positive.size == 0:
        return None
    return max(MIN_WINDOW_NS, math.ceil(2.0 * float(np.median(positive))))


def _window_bounds(mono_ns: npt.NDArray[np.int64], window_ns: int | None) -> npt.NDArray[np.int64]:
    """Sample indices bounding consecutive windows; the last one may end before the final sample."""
    if window_ns is None:
        return np.zeros(0, dtype=np.int64)
    count = mono_ns.size
    bounds = [0]
    while True:
        nxt = int(np.searchsorted(mono_ns, mono_ns[bounds[-1]] + window_ns, side="left"))
        if nxt >= count:
            break
        bounds.append(nxt)
    if len(bounds) == 1:
        bounds.append(count - 1)  # shorter than one window: measure over everything
    return np.asarray(bounds, dtype=np.int64)


def _unwrapped_yaw(yaw: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    """Continuous heading, carried forward over unknown samples; NaN before the first known one."""
    known = np.flatnonzero(np.isfinite(yaw))
    result = np.full(yaw.shape, np.nan)
    if known.size == 0:
        return result
    steps = np.diff(yaw[known])
    wrapped = (steps + math.pi) % (2.0 * math.pi) - math.pi
    result[known] = yaw[known[0]] + np.concatenate(([0.0], np.cumsum(wrapped)))
    last_known = np.maximum.accumulate(np.where(np.isfinite(yaw), np.arange(yaw.size), -1))
    filled = result[np.maximum(last_known, 0)]
    return np.where(last_known >= 0, filled, np.nan)


def _runs(mask: npt.NDArray[np.bool_]) -> list[tuple[int, int]]:
    """Inclusive (first, last) positions of the runs of True in mask."""
    edges = np.diff(np.concatenate(([0], mask.astype(np.int8), [0])))
    firsts = np.flatnonzero(edges == 1)
    lasts = np.flatnonzero(edges == -1) - 1
    return list(zip(firsts.tolist(), lasts.tolist(), strict=True))


def _sample_runs(
    mask: npt.NDArray[np.bool_], starts: npt.NDArray[np.int64], span_ends: npt.NDArray[np.int64]
) -> list[tuple[slice, int, int]]:
    """Each run of windows where ``mask`` holds: its windows, and the first and last sample it spans."""
    return [(slice(first, last + 1), int(starts[first]), int(span_ends[last])) for first, last in _runs(mask)]


def _stops(runs: list[tuple[slice, int, int]], elapsed_s: npt.NDArray[np.float64]) -> list[Stop]:
    """The stopped runs that last at least MIN_STOP_S."""
    stops = [Stop(start, end, float(elapsed_s[windows].sum())) for windows, start, end in runs]
    return [stop for stop in stops if stop.duration_s >= MIN_STOP_S - 1e-9]


def _stationary_runs(runs: list[tuple[slice, int, int]], unwrapped: npt.NDArray[np.float64]) -> list[StationaryRun]:
    """The stationary runs with their heading change (None where the heading is unknown)."""
    turns = [(start, end, float(unwrapped[end] - unwrapped[start])) for _, start, end in runs]
    return [StationaryRun(start, end, turn if math.isfinite(turn) else None) for start, end, turn in turns]
