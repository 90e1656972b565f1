"""What analyze_trajectory answers."""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, ConfigDict, Field

from bagmcp_analysis.trajectory.types import Extents, TrackTotals
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


class _Track(BaseModel):
    """Which track a report is about (its fields come first in the report)."""

    bag: str
    topic: str
    type: str
    frame: str | None = Field(description="frame of the poses (metres east/north from the first fix for GPS)")
    alternatives: list[str] = Field(description="other pose topics")
    clock: Literal["header", "log_time"] = Field(description="clock used for speeds and durations")
    start: Instant
    end: Instant


class TrajectoryReport(TrackTotals, _Track):
    # The track (_Track), then the summary's totals as they are (TrackTotals), then what a report adds; no
    # docstring, which would become the output schema's description.
    model_config = ConfigDict(frozen=False)

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
