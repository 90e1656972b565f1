"""LaserScan geometry at full resolution: return counts, range statistics, closest hit, sectors, free gaps,
and per-scan minimum series (first approach within a distance, downsampled minimum profile)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from bagmcp_analysis.lidar.gaps import FreeGap, free_gaps
from bagmcp_analysis.lidar.geometry import beam_bearings_deg
from bagmcp_analysis.lidar.sectors import Sector, sector_stats
from bagmcp_analysis.lidar.series import Approach, first_within, minimum_profile
from bagmcp_shared.laser_ranges import LaserRanges

__all__ = [
    "Approach",
    "FreeGap",
    "Hit",
    "LaserRanges",
    "ScanStats",
    "Sector",
    "first_within",
    "minimum_profile",
    "scan_stats",
]


@dataclass(frozen=True)
class Hit:
    """A single beam return: range, bearing in (-180, 180] degrees and beam index."""

    range_m: float
    bearing_deg: float
    index: int


@dataclass(frozen=True)
class ScanStats:
    """Counts of every kind of return, statistics of the valid ranges, closest hit, sectors and free gaps."""

    beams: int
    valid: int
    nan: int
    pos_inf: int
    neg_inf: int
    below_min: int
    above_max: int
    min_m: float | None
    max_m: float | None
    mean_m: float | None
    median_m: float | None
    closest: Hit | None
    sectors: list[Sector]
    free_gaps: list[FreeGap]


def _check_scan(scan: LaserRanges, ranges: npt.NDArray[np.float64]) -> None:
    if ranges.ndim != 1:
        raise ValueError(f"Scan ranges must be a 1-D array of metres (got shape {ranges.shape}).")
    if not math.isfinite(scan.angle_min) or not math.isfinite(scan.angle_increment) or scan.angle_increment == 0:
        raise ValueError(
            f"Scan angles are unusable (angle_min={scan.angle_min}, angle_increment={scan.angle_increment}); "
            "angle_increment must be finite and non-zero."
        )
    if math.isnan(scan.range_min) or math.isnan(scan.range_max):
        raise ValueError("Scan range_min and range_max must be numbers, not NaN.")


def _summary(good: npt.NDArray[np.float64]) -> tuple[float | None, float | None, float | None, float | None]:
    """Min, max, mean and median of the valid ranges (all None when there are none)."""
    if good.size == 0:
        return None, None, None, None
    return float(good.min()), float(good.max()), float(good.mean()), float(np.median(good))


def scan_stats(
    scan: LaserRanges, *, sectors: int = 8, free_range_m: float | None = None, max_gaps: int = 6
) -> ScanStats:
    """Full-resolution geometry of one scan; valid beams are finite with range_min <= r <= range_max."""
    ranges = np.asarray(scan.ranges, dtype=np.float64)
    _check_scan(scan, ranges)
    if max_gaps < 0:
        raise ValueError(f"max_gaps must be zero or more (got {max_gaps}).")
    finite = np.isfinite(ranges)
    with np.errstate(invalid="ignore"):
        below = finite & (ranges < scan.range_min)
        above = finite & (ranges > scan.range_max)
    valid = finite & ~below & ~above
    bearings = beam_bearings_deg(ranges.shape[0], angle_min=scan.angle_min, angle_increment=scan.angle_increment)
    good = ranges[valid]
    closest: Hit | None = None
    if good.size:
        index = int(np.flatnonzero(valid)[int(np.argmin(good))])
        closest = Hit(range_m=float(ranges[index]), bearing_deg=float(bearings[index]), index=index)
    min_m, max_m, mean_m, median_m = _summary(good)
    threshold = 0.8 * scan.range_max if free_range_m is None else free_range_m
    return ScanStats(
        beams=int(ranges.shape[0]),
        valid=int(valid.sum()),
        nan=int(np.isnan(ranges).sum()),
        pos_inf=int(np.isposinf(ranges).sum()),
        neg_inf=int(np.isneginf(ranges).sum()),
        below_min=int(below.sum()),
        above_max=int(above.sum()),
        min_m=min_m,
        max_m=max_m,
        mean_m=mean_m,
        median_m=median_m,
        closest=closest,
        sectors=sector_stats(ranges, valid, bearings, sectors=sectors),
        free_gaps=free_gaps(
            ranges,
            valid,
            bearings,
            angle_increment=scan.angle_increment,
            range_max=scan.range_max,
            free_range_m=threshold,
            max_gaps=max_gaps,
        ),
    )
