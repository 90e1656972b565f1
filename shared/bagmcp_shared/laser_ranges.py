"""One sensor_msgs/LaserScan as typed arrays: decoded here once for the index, analysis, plotting and the
viewers, which used to read its fields by name in four places. ``MOVING_MPS`` lives beside it for the same
reason: analysis (stops) and plotting (when motion starts) must agree on what moving means."""

from __future__ import annotations

from dataclasses import dataclass
from operator import attrgetter

import numpy as np
import numpy.typing as npt

_FIELDS = attrgetter("ranges", "angle_min", "angle_increment", "range_min", "range_max")
MOVING_MPS = 0.05  # a pose slower than this (m/s) is stopped: analyze_trajectory's stops, plots' motion start


@dataclass(frozen=True, eq=False)
class LaserRanges:
    """Ranges in metres and angles in radians (REP 103, counter-clockwise positive)."""

    ranges: npt.NDArray[np.float64]
    angle_min: float
    angle_increment: float
    range_min: float
    range_max: float

    @property
    def valid(self) -> npt.NDArray[np.bool_]:
        """Finite ranges inside range_min..range_max (what a sensor reports as a return)."""
        r = self.ranges
        return np.isfinite(r) & (r >= self.range_min) & (r <= self.range_max)

    @property
    def angles(self) -> npt.NDArray[np.float64]:
        return (self.angle_min + np.arange(self.ranges.size) * self.angle_increment).astype(np.float64)

    def closest(self) -> tuple[float, float] | None:
        """The closest valid return and its bearing in radians, or None when no beam is valid."""
        valid = self.valid
        if not valid.any():
            return None
        index = int(np.argmin(np.where(valid, self.ranges, np.inf)))
        return float(self.ranges[index]), self.angle_min + index * self.angle_increment


def laser_ranges(message: object) -> LaserRanges:
    """A decoded LaserScan message (any of rosbags' or the foreign readers' message classes)."""
    ranges, angle_min, angle_increment, range_min, range_max = _FIELDS(message)
    return LaserRanges(
        ranges=np.asarray(ranges, dtype=np.float64),
        angle_min=float(angle_min),
        angle_increment=float(angle_increment),
        range_min=float(range_min),
        range_max=float(range_max),
    )
