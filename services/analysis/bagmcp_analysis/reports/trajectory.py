"""What analyze_trajectory answers."""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, Field

from bagmcp_analysis.trajectory.types import Extents
from bagmcp_shared.timebase import Instant


class Pose(BaseModel):
    x: float = Field(description="m")
    y: float = Field(description="m")
    z: float | None = Field(description="m")
    yaw_deg: float | None
    time: Instant


class Waypoint(Pose):
    reason: Literal["start", "corner", "stop", "end"]


class StopOut(BaseModel):
    start: Instant
    end: Instant
    duration_s: float


class TrajectoryReport(BaseModel):
    bag: str
    topic: str
    type: str
    frame: str | None = Field(description="frame of the poses (metres east/north from the first fix for GPS)")
    alternatives: list[str] = Field(description="other pose topics")
    clock: Literal["header", "log_time"] = Field(description="clock used for speeds and durations")
    start: Instant
    end: Instant
    samples: int
    duration_s: float
    distance_2d_m: float
    distance_3d_m: float | None
    displacement_2d_m: float
    displacement_3d_m: float | None
    path_efficiency: float | None = Field(description="displacement / distance (2D)")
    mean_speed_mps: float | None = Field(description="distance / duration")
    mean_moving_speed_mps: float | None = Field(description="distance / moving time")
    max_speed_mps: float | None
    max_speed_at: Instant | None
    moving_s: float = Field(description="driving or turning")
    stopped_s: float
    stops: list[StopOut]
    extents: Extents = Field(description="bounding box in m")
    start_pose: Pose
    end_pose: Pose
    waypoints: list[Waypoint]
    notes: list[str]
