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


@dataclass(frozen=True, eq=False)
class _Path:
    """The positions, their stationary runs, and the RDP tolerance corners are found and merged with."""

    x: npt.NDArray[np.float64]
    y: npt.NDArray[np.float64]
    stationary: list[StationaryRun]
    tolerance_m: float

    def run_at(self, index: int) -> StationaryRun | None:
        """The stationary run containing index, or the neighbouring run reached without leaving the tolerance."""
        runs = self.stationary
        position = bisect.bisect_right([run.start_index for run in runs], index) - 1
        if position >= 0:
            before = runs[position]
            if index <= before.end_index or self.stays_within(before.end_index, index, index):
                return before
        if position + 1 < len(runs):
            after = runs[position + 1]
            if self.stays_within(index, after.start_index, index):
                return after
        return None

    def stays_within(self, lo: int, hi: int, centre: int) -> bool:
        spread = np.hypot(self.x[lo : hi + 1] - self.x[centre], self.y[lo : hi + 1] - self.y[centre])
        return bool(spread.max() <= self.tolerance_m)


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
    candidates = _corner_candidates(_Path(x, y, stationary, rdp_tolerance_m(x, y)), stops)
    ranked = sorted(candidates, key=lambda c: (-c.significance, c.index))[: max_waypoints - 2]
    middle = [Waypoint(c.index, c.reason) for c in sorted(ranked, key=lambda c: c.index)]
    return [Waypoint(0, "start"), *middle, Waypoint(last, "end")]


def _corner_candidates(path: _Path, stops: list[Stop]) -> list[_Candidate]:
    last = path.x.size - 1
    run_significance: dict[int, float] = {}
    for run in path.stationary:
        if run.turn_rad is not None and abs(run.turn_rad) > MIN_TURN_RAD:
            run_significance[run.start_index] = abs(run.turn_rad) / MIN_TURN_RAD
    loose: list[_Candidate] = []
    for index, deviation_m in rdp_corners(path.x, path.y, path.tolerance_m).items():
        found = path.run_at(index)
        significance = deviation_m / path.tolerance_m
        if found is None:
            loose.append(_Candidate(index, significance, "corner"))
        else:
            previous = run_significance.get(found.start_index, 0.0)
            run_significance[found.start_index] = max(previous, significance)
    by_start = {run.start_index: run for run in path.stationary}
    merged = [
        _Candidate(start, significance, "stop" if _has_stop(by_start[start], stops) else "corner")
        for start, significance in run_significance.items()
        if start > 0 and by_start[start].end_index < last
    ]
    return loose + merged


def _has_stop(run: StationaryRun, stops: list[Stop]) -> bool:
    return any(run.start_index <= stop.start_index and stop.end_index <= run.end_index for stop in stops)
