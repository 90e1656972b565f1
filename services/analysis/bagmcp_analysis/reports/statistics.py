"""What topic_statistics answers."""

from __future__ import annotations

from pydantic import BaseModel, Field

from bagmcp_analysis.timing import HeaderTiming
from bagmcp_shared.timebase import Instant


class GapOut(BaseModel):
    start: Instant = Field(description="last message before the silence")
    end: Instant
    length_s: float
    periods: float = Field(description="length in median periods")


class TopicStatisticsReport(BaseModel):
    bag: str
    topic: str
    type: str
    count: int
    start: Instant | None
    end: Instant | None
    clock: str = Field(description="periods and gaps use log (receive) time")
    rate_hz: float | None = Field(description="(count - 1) / span")
    nominal_rate_hz: float | None = Field(description="1 / median period")
    median_period_s: float | None
    jitter_s: float | None = Field(description="standard deviation of periods")
    jitter_p95_s: float | None = Field(description="95th percentile of |period - median|")
    min_period_s: float | None
    max_period_s: float | None
    gaps: list[GapOut] = Field(description="longest first")
    gap_count: int
    dropped_estimate: int = Field(description="messages the gaps would have held at the median rate")
    duplicates: int = Field(description="repeated log times")
    out_of_order: int = Field(description="log times going backwards")
    header: HeaderTiming | None = Field(description="header stamps: delay = log time - header stamp")
    source: str
