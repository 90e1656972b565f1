"""Angular sectors of a LaserScan (front, front-left, ... for 8 sectors) with their closest valid return."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from bagmcp_analysis.lidar.geometry import normalize_deg

EIGHT_SECTOR_NAMES = ("front", "front-left", "left", "back-left", "back", "back-right", "right", "front-right")


@dataclass(frozen=True)
class Sector:
    """Sector spanning counter-clockwise from from_deg to to_deg; valid counts the valid beams inside it."""

    name: str
    center_deg: float
    from_deg: float
    to_deg: float
    valid: int
    closest_m: float | None
    closest_bearing_deg: float | None


def sector_index(bearings_deg: npt.NDArray[np.float64], *, sectors: int) -> npt.NDArray[np.int64]:
    """Sector number of every bearing; sector k is centred on k * 360 / sectors degrees (half-open at the CCW end)."""
    width = 360.0 / sectors
    raw = np.floor((bearings_deg + width / 2.0) / width + 1e-9).astype(np.int64)
    result: npt.NDArray[np.int64] = np.mod(raw, sectors)
    return result


def sector_name(k: int, *, sectors: int) -> str:
    """Compass-style name for 8 sectors, else "sector k"."""
    return EIGHT_SECTOR_NAMES[k] if sectors == len(EIGHT_SECTOR_NAMES) else f"sector {k}"


def sector_stats(
    ranges: npt.NDArray[np.float64],
    valid: npt.NDArray[np.bool_],
    bearings_deg: npt.NDArray[np.float64],
    *,
    sectors: int,
) -> list[Sector]:
    """One Sector per angular slice; only valid beams that fall inside a slice count for it."""
    if sectors < 1:
        raise ValueError(f"sectors must be at least 1 (got {sectors}); use 8 for front/left/back/right slices.")
    width = 360.0 / sectors
    index = sector_index(bearings_deg, sectors=sectors)
    result: list[Sector] = []
    for k in range(sectors):
        members = np.flatnonzero((index == k) & valid)
        closest_m: float | None = None
        closest_bearing: float | None = None
        if members.size:
            best = int(members[int(np.argmin(ranges[members]))])
            closest_m = float(ranges[best])
            closest_bearing = float(bearings_deg[best])
        center = normalize_deg(k * width)
        result.append(
            Sector(
                name=sector_name(k, sectors=sectors),
                center_deg=center,
                from_deg=normalize_deg(center - width / 2.0),
                to_deg=normalize_deg(center + width / 2.0),
                valid=int(members.size),
                closest_m=closest_m,
                closest_bearing_deg=closest_bearing,
            )
        )
    return result
