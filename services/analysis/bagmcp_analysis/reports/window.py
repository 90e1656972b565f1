"""What summarize_window answers: evidence about a window an agent can quote, every statement with numbers."""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, Field

from bagmcp_analysis.reports.lidar import Closest
from bagmcp_analysis.reports.logs import LogEntry
from bagmcp_analysis.reports.trajectory import StopOut
from bagmcp_shared.timebase import Instant

TopicStatus = Literal["ok", "slow", "late", "silent", "gap", "absent"]


class TopicActivity(BaseModel):
    topic: str
    count: int = Field(description="messages in the window")
    rate_hz: float | None = Field(description="in the window")
    bag_rate_hz: float | None = Field(description="over the whole bag")
    longest_silence_s: float | None = Field(description="longest time without a message inside the window")
    silent_from: Instant | None
    delay_s: float | None = Field(description="median log time - header stamp in the window")
    bag_delay_s: float | None = Field(
        description="the same over the bag (a topic the index does not hold: sampled in 8 stretches across it)"
    )
    status: TopicStatus = Field(
        description="slow: under half its bag rate; gap: silent over 3 periods; late: delay over twice "
        "the bag's and 50 ms more; absent: not recorded then"
    )


class Motion(BaseModel):
    topic: str
    distance_m: float
    mean_speed_mps: float | None
    max_speed_mps: float | None
    moving_s: float
    stopped_s: float
    stops: list[StopOut] = Field(description="the first stops in the window")
    stop_count: int


class FlightMode(BaseModel):
    mode: str
    value: int = Field(description="the log's own number (PX4 nav_state, ArduPilot mode number)")
    since: Instant = Field(description="when it took effect (before the window for the first one)")


class WindowReport(BaseModel):
    bag: str
    start: Instant
    end: Instant
    statements: list[str] = Field(description="what happened, with numbers and times")
    topics: list[TopicActivity] = Field(description="topics that were not ok first (bounded)")
    topics_total: int = Field(description="topics with messages in the bag")
    topics_by_status: dict[str, int]
    warnings: dict[str, int] = Field(description="log records at WARN or above by level")
    log_entries: list[LogEntry] = Field(description="the first WARN-or-worse records")
    motion: Motion | None
    closest_obstacle: Closest | None
    flight_modes: list[FlightMode] = Field(
        default_factory=list, description="flight logs: the mode at the window start, then every change"
    )
