"""Per-scan minimum-range series: first approach within a distance, and a downsampled minimum profile."""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from bagmcp_analysis.lidar.geometry import normalize_deg


@dataclass(frozen=True)
class Approach:
    """First scan whose minimum range is below the distance, and how long things stayed that close.

    stays_s runs to the first later scan that is no longer closer, or to the last scan when until_end is True;
    total_within_s sums the periods of all closer scans; episodes counts separate runs of closer scans.
    """

    index: int
    t_ns: int
    range_m: float
    bearing_deg: float | None
    stays_s: float
    until_end: bool
    total_within_s: float
    episodes: int


def _series(t_ns: npt.ArrayLike, min_range_m: npt.ArrayLike) -> tuple[npt.NDArray[np.int64], npt.NDArray[np.float64]]:
    times = np.asarray(t_ns, dtype=np.int64).reshape(-1)
    ranges = np.asarray(min_range_m, dtype=np.float64).reshape(-1)
    if times.shape != ranges.shape:
        raise ValueError(f"t_ns and min_range_m must have the same length (got {times.size} and {ranges.size}).")
    if times.size > 1 and bool(np.any(np.diff(times) < 0)):
        raise ValueError("t_ns must be sorted in increasing time order; sort the scans by stamp first.")
    return times, ranges


def _periods_s(times: npt.NDArray[np.int64]) -> npt.NDArray[np.float64]:
    """Time from each scan to the next; the last scan gets the median period (0 for a single scan)."""
    gaps = np.diff(times).astype(np.float64) / 1e9
    last = float(np.median(gaps)) if gaps.size else 0.0
    return np.append(gaps, last)


def first_within(
    t_ns: npt.ArrayLike,
    min_range_m: npt.ArrayLike,
    min_bearing_rad: npt.ArrayLike,
    *,
    distance_m: float,
) -> Approach | None:
    """First scan with minimum range < distance_m (NaN = no valid beam, never closer); None when never closer."""
    times, ranges = _series(t_ns, min_range_m)
    bearings = np.asarray(min_bearing_rad, dtype=np.float64).reshape(-1)
    if bearings.shape != ranges.shape:
        raise ValueError("min_bearing_rad must have one bearing per scan, like min_range_m.")
    if not math.isfinite(distance_m) or distance_m <= 0:
        raise ValueError(f"distance_m must be a positive number of metres (got {distance_m}).")
    with np.errstate(invalid="ignore"):
        closer = ranges < distance_m
    if not bool(closer.any()):
        return None
    first = int(np.argmax(closer))
    left = np.flatnonzero(~closer[first:])
    end = first + int(left[0]) if left.size else int(times.size - 1)
    bearing = float(bearings[first])
    rising = int(closer[0]) + int(np.count_nonzero(closer[1:] & ~closer[:-1]))
    return Approach(
        index=first,
        t_ns=int(times[first]),
        range_m=float(ranges[first]),
        bearing_deg=normalize_deg(math.degrees(bearing)) if math.isfinite(bearing) else None,
        stays_s=float(times[end] - times[first]) / 1e9,
        until_end=not bool(left.size),
        total_within_s=float(_periods_s(times)[closer].sum()),
        episodes=rising,
    )


def minimum_profile(
    t_ns: npt.ArrayLike, min_range_m: npt.ArrayLike, *, max_points: int = 200
) -> tuple[list[int], list[float | None]]:
    """At most max_points (t_ns, range) pairs: each bucket of consecutive scans keeps its minimum and that
    scan's time (the first scan's time and None when the bucket has no valid range), so the global minimum
    always survives."""
    if max_points < 1:
        raise ValueError(f"max_points must be at least 1 (got {max_points}).")
    times, ranges = _series(t_ns, min_range_m)
    if times.size <= max_points:
        return [int(t) for t in times], [float(r) if math.isfinite(r) else None for r in ranges]
    bounds = np.linspace(0, times.size, max_points + 1).astype(np.int64)
    out_t: list[int] = []
    out_r: list[float | None] = []
    for start, stop in itertools.pairwise(bounds):
        bucket = ranges[start:stop]
        finite = np.isfinite(bucket)
        if not bool(finite.any()):
            out_t.append(int(times[start]))
            out_r.append(None)
            continue
        best = int(start) + int(np.argmin(np.where(finite, bucket, np.inf)))
        out_t.append(int(times[best]))
        out_r.append(float(ranges[best]))
    return out_t, out_r
