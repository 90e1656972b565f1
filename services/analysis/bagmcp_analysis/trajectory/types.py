"""Input and result types of the trajectory summary: Track, Stop, Extents, Waypoint and TrackSummary."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np
import numpy.typing as npt
from pydantic import BaseModel, ConfigDict

Clock = Literal["header", "log_time"]
WaypointReason = Literal["start", "corner", "stop", "end"]


@dataclass(frozen=True, eq=False)
class Track:
    """Poses in message order (time order of the chosen clock); metres in a local frame (REP 103).

    `yaw` is in radians, NaN where unknown; `z` may be NaN where the altitude is unknown. `log_time` says the
    stamps are arrival (log) times rather than the sensor's own: a recorder that stalls then writes a burst puts
    the motion of the stall into the burst, so speeds count time by messages there (see motion.py).
    """

    t_ns: npt.NDArray[np.int64]
    x: npt.NDArray[np.float64]
    y: npt.NDArray[np.float64]
    z: npt.NDArray[np.float64]
    yaw: npt.NDArray[np.float64]
    log_time: bool = False

    def __post_init__(self) -> None:
        object.__setattr__(self, "t_ns", np.asarray(self.t_ns, dtype=np.int64))
        for name in ("x", "y", "z", "yaw"):
            object.__setattr__(self, name, np.asarray(getattr(self, name), dtype=np.float64))
        if self.t_ns.ndim != 1:
            raise ValueError("Track stamps must be a one-dimensional array; pass one stamp per pose.")
        for name, values in (("x", self.x), ("y", self.y), ("z", self.z), ("yaw", self.yaw)):
            if values.shape != self.t_ns.shape:
                raise ValueError(
                    f"Track field {name!r} has {values.size} values for {self.t_ns.size} stamps; pass one per pose."
                )


@dataclass(frozen=True)
class Stop:
    """A stopped interval: sample indices (inclusive) and its length in seconds."""

    start_index: int
    end_index: int
    duration_s: float


@dataclass(frozen=True)
class Extents:
    """Bounding box of the poses in metres; z bounds are None when no altitude is known."""

    min_x: float
    max_x: float
    min_y: float
    max_y: float
    min_z: float | None
    max_z: float | None


@dataclass(frozen=True)
class Waypoint:
    """A sample worth naming when describing the path: start, corner, stop (stopped there) or end."""

    index: int
    reason: WaypointReason


class TrackTotals(BaseModel):
    """How much of a track there is: the figures a summary computes and its report states as they are.

    A pydantic model so that the report (reports/trajectory.py) takes these fields from here rather than
    declaring them again; numpy scalars given to it become Python numbers."""

    model_config = ConfigDict(frozen=True)

    samples: int
    duration_s: float
    distance_2d_m: float
    distance_3d_m: float | None
    displacement_2d_m: float
    displacement_3d_m: float | None


class TrackSummary(TrackTotals):
    """Distances in metres, times in seconds, speeds in m/s; None where a value is undefined."""

    path_efficiency: float | None
    mean_speed_mps: float | None
    mean_moving_speed_mps: float | None
    max_speed_mps: float | None
    max_speed_index: int | None
    moving_s: float
    stopped_s: float
    stops: list[Stop]
    extents: Extents
    start_index: int
    end_index: int
    waypoints: list[Waypoint]
    notes: list[str]
