"""Free-space gaps in a LaserScan: maximal runs of beams with a far or no return, wrap-around aware."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from bagmcp_analysis.lidar.geometry import covers_full_circle, normalize_deg


@dataclass(frozen=True)
class FreeGap:
    """A run of free beams spanning counter-clockwise from from_deg to to_deg (beam centres)."""

    from_deg: float
    to_deg: float
    width_deg: float
    nearest_m: float | None


def _runs(free: npt.NDArray[np.bool_]) -> list[tuple[int, int]]:
    """(start, length) of each maximal run of True values, in index order."""
    padded = np.concatenate(([0], free.astype(np.int8), [0]))
    steps = np.diff(padded)
    starts = np.flatnonzero(steps == 1)
    ends = np.flatnonzero(steps == -1)
    return [(int(s), int(e - s)) for s, e in zip(starts, ends, strict=True)]


def _join_wrap(runs: list[tuple[int, int]], beams: int) -> list[tuple[int, int]]:
    """Merge the run ending at the last beam into the run starting at beam 0 (a full-circle scan)."""
    if len(runs) < 2 or runs[0][0] != 0 or runs[-1][0] + runs[-1][1] != beams:
        return runs
    last_start, last_length = runs[-1]
    return [(last_start, last_length + runs[0][1]), *runs[1:-1]]


def free_gaps(
    ranges: npt.NDArray[np.float64],
    valid: npt.NDArray[np.bool_],
    bearings_deg: npt.NDArray[np.float64],
    *,
    angle_increment: float,
    range_max: float,
    free_range_m: float,
    max_gaps: int,
) -> list[FreeGap]:
    """Widest-first free gaps: valid beams at >= free_range_m, or +inf / beyond range_max (no return)."""
    beams = int(ranges.shape[0])
    with np.errstate(invalid="ignore"):
        no_return = np.isposinf(ranges) | (np.isfinite(ranges) & (ranges > range_max))
        free = (valid & (ranges >= free_range_m)) | no_return
    runs = _runs(free)
    if covers_full_circle(beams, angle_increment=angle_increment):
        runs = _join_wrap(runs, beams)
    runs.sort(key=lambda run: -run[1])
    step_deg = math.degrees(abs(angle_increment))
    gaps: list[FreeGap] = []
    for start, length in runs[:max_gaps]:
        indices = (start + np.arange(length)) % beams
        inside = ranges[indices][valid[indices]]
        first, last = float(bearings_deg[indices[0]]), float(bearings_deg[indices[-1]])
        if angle_increment < 0:
            first, last = last, first
        gaps.append(
            FreeGap(
                from_deg=normalize_deg(first),
                to_deg=normalize_deg(last),
                width_deg=(length - 1) * step_deg,
                nearest_m=float(inside.min()) if inside.size else None,
            )
        )
    return gaps
