"""What analyze_lidar_scan answers: one scan (or cloud) in full, or a window of per-scan minima."""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, Field

from bagmcp_analysis.lidar.pointcloud import CloudStats
from bagmcp_analysis.lidar.scan import ScanStats
from bagmcp_shared.timebase import Instant


class Closest(BaseModel):
    range_m: float
    bearing_deg: float | None = Field(description="0 = forward, + = left (REP 103)")
    time: Instant


class FirstWithin(Closest):
    """The first scan closer than ``within_m``, and how long something stayed that close."""

    stays_s: float = Field(description="until the first later scan that is no longer closer")
    until_end: bool = Field(description="still closer at the last scan of the window")
    total_within_s: float
    episodes: int = Field(description="separate times it came closer")


class MinimumProfile(BaseModel):
    """Per-scan minimum range over the window, downsampled keeping each bucket's minimum."""

    offset_s: list[float] = Field(description="s from bag start")
    range_m: list[float | None]


class LidarReport(BaseModel):
    bag: str
    topic: str
    type: str
    frame: str | None
    mode: Literal["scan", "window"]
    time: Instant | None = Field(description="stamp of the scan shown (mode scan)")
    delta_s: float | None = Field(description="scan time minus requested time")
    scan: ScanStats | None = Field(description="LaserScan at full resolution (mode scan)")
    cloud: CloudStats | None = Field(description="PointCloud2 (mode scan)")
    start: Instant | None
    end: Instant | None
    scans: int | None = Field(description="scans in the window")
    closest: Closest | None = Field(description="closest return in the window")
    within_m: float | None
    first_within: FirstWithin | None
    minimum: MinimumProfile | None
    source: Literal["index", "bag"]
