"""Shared LaserScan geometry helpers: beam bearings (REP 103, degrees in (-180, 180]) and scan coverage."""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt


def normalize_deg(angle_deg: float) -> float:
    """Angle in degrees mapped to (-180, 180]."""
    return 180.0 - (180.0 - angle_deg) % 360.0


def normalize_deg_array(angles_deg: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    """Element-wise normalize_deg for arrays."""
    result: npt.NDArray[np.float64] = 180.0 - np.mod(180.0 - angles_deg, 360.0)
    return result


def beam_bearings_deg(beams: int, *, angle_min: float, angle_increment: float) -> npt.NDArray[np.float64]:
    """Bearing of every beam in degrees, 0 = forward, counter-clockwise positive, in (-180, 180]."""
    radians = angle_min + angle_increment * np.arange(beams, dtype=np.float64)
    return normalize_deg_array(np.degrees(radians))


def covers_full_circle(beams: int, *, angle_increment: float) -> bool:
    """True when the beams sweep a whole turn (to within half a beam spacing)."""
    step = abs(angle_increment)
    return beams * step >= 2.0 * math.pi - 0.5 * step
