"""Waypoints of a track: start, corners (Ramer-Douglas-Peucker plus stop-turn-go turns in place), end.

Significance of a corner is how many times it exceeds its threshold: RDP deviation / tolerance, or heading
change / 30 degrees for a turn in place. The least significant corners are dropped first.
"""

from __future__ import annotations

import bisect
import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from bagmcp_analysis.trajectory.motion import StationaryRun
from bagmcp_analysis.trajectory.types import Stop, Waypoint, WaypointReason

MIN_TOLERANCE_M = 0.05
TOLERANCE_FRACTION = 0.02
MIN_TURN_RAD = math.radians(30.0)


@dataclass(frozen=True)
class _Candidate:
    index: int
    significance: float
    reason: WaypointReason


def rdp_tolerance_m(x: npt.NDArray[np.float64], y: npt.NDArray[np.float64]) -> float:
    """max(0.05 m, 2 % of the diagonal of the 2D extents)."""
    diagonal = math.hypot(float(x.max() - x.min()), float(y.max() - y.min()))
    return max(MIN_TOLERANCE_M, TOLERANCE_FRACTION * diagonal)


def rdp_corners(x: npt.NDArray[np.float64], y: npt.NDArray[np.float64], tolerance_m: float) -> dict[int, float]:
    """Interior indices kept by Ramer-Douglas-Peucker, mapped to their deviation (m) when kept."""
    kept: dict[int, float] = {}
    pending = [(0, x.size - 1)]
    while pending:
        first, last = pending.pop()
        if last - first < 2:
            continue
        deviation = _segment_distances(x[first + 1 : last], y[first + 1 : last], x, y, first, last)
        offset = int(np.argmax(deviation))
        if float(deviation[offset]) > tolerance_m:
            index = first + 1 + offset
            kept[index] = float(deviation[offset])
            pending.extend([(first, index), (index, last)])
    return kept


def _segment_distances(
    px: npt.NDArray[np.float64],
    py: npt.NDArray[np.float64],
    x: npt.NDArray[np.float64],
    y: npt.NDArray[np.float64],
    first: int,
    last: int,
) -> npt.NDArray[np.float64]:
    """Distance of points to the segment from sample `first` to sample `last` (not the infinite line)."""
    ax, ay = float(x[first]), float(y[first])
    dx, dy = float(x[last]) - ax, float(y[last]) - ay
    length_sq = dx * dx + dy * dy
    if length_sq == 0.0:
        return np.hypot(px - ax, py - ay)
    along = np.clip(((px - ax) * dx + (py - ay) * dy) / length_sq, 0.0, 1.0)
    return np.hypot(px - (ax + along * dx), py - (ay + along * dy))


def select_waypoints(
    x: npt.NDArray[np.float64],
    y: npt.NDArray[np.float64],
    stationary: list[StationaryRun],
    stops: list[Stop],
    *,
    max_waypoints: int,
) -> list[Waypoint]:
    """Start, the most significant corners (at most max_waypoints - 2), end; in index order."""
    last = x.size - 1
    if last == 0:
        return [Waypoint(0, "start")]
    tolerance_m = rdp_tolerance_m(x, y)
    candidates = _corner_candidates(x, y, stationary, stops, tolerance_m)
    ranked = sorted(candidates, key=lambda c: (-c.significance, c.index))[: max_waypoints - 2]
    middle = [Waypoint(c.index, c.reason) for c in sorted(ranked, key=lambda c: c.index)]
    return [Waypoint(0, "start"), *middle, Waypoint(last, "end")]


def _corner_candidates(
    x: npt.NDArray[np.float64],
    y: npt.NDArray[np.float64],
    stationary: list[StationaryRun],
    stops: list[Stop],
    tolerance_m: float,
) -> list[_Candidate]:
    last = x.size - 1
    run_significance: dict[int, float] = {}
    for run in stationary:
        if run.turn_rad is not None and abs(run.turn_rad) > MIN_TURN_RAD:
            run_significance[run.start_index] = abs(run.turn_rad) / MIN_TURN_RAD
    loose: list[_Candidate] = []
    for index, deviation_m in rdp_corners(x, y, tolerance_m).items():
        found = _run_at(x, y, stationary, index, tolerance_m)
        significance = deviation_m / tolerance_m
        if found is None:
            loose.append(_Candidate(index, significance, "corner"))
        else:
            previous = run_significance.get(found.start_index, 0.0)
            run_significance[found.start_index] = max(previous, significance)
    by_start = {run.start_index: run for run in stationary}
    merged = [
        _Candidate(start, significance, "stop" if _has_stop(by_start[start], stops) else "corner")
        for start, significance in run_significance.items()
        if start > 0 and by_start[start].end_index < last
    ]
    return loose + merged


def _run_at(
    x: npt.NDArray[np.float64],
    y: npt.NDArray[np.float64],
    stationary: list[StationaryRun],
    index: int,
    tolerance_m: float,
) -> StationaryRun | None:
    """The stationary run containing index, or the neighbouring run reached without leaving the tolerance."""
    position = bisect.bisect_right([run.start_index for run in stationary], index) - 1
    if position >= 0:
        before = stationary[position]
        if index <= before.end_index or _stays_within(x, y, before.end_index, index, index, tolerance_m):
            return before
    if position + 1 < len(stationary):
        after = stationary[position + 1]
        if _stays_within(x, y, index, after.start_index, index, tolerance_m):
            return after
    return None


def _stays_within(
    x: npt.NDArray[np.float64], y: npt.NDArray[np.float64], lo: int, hi: int, centre: int, radius_m: float
) -> bool:
    spread = np.hypot(x[lo : hi + 1] - x[centre], y[lo : hi + 1] - y[centre])
    return bool(spread.max() <= radius_m)


def _has_stop(run: StationaryRun, stops: list[Stop]) -> bool:
    return any(run.start_index <= stop.start_index and stop.end_index <= run.end_index for stop in stops)
