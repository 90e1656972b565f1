"""What analyze_logs answers: matching records (paged) and a summary."""

from __future__ import annotations

from pydantic import BaseModel, Field

from bagmcp_shared.timebase import Instant


class LogEntry(BaseModel):
    time: Instant = Field(description="log time")
    level: str
    node: str
    text: str
    source: str = Field(description="file:line (function)")


class BurstOut(BaseModel):
    start: Instant
    end: Instant
    count: int
    top_node: str
    worst_level: str


class LogSummaryOut(BaseModel):
    by_level: dict[str, int]
    by_node: dict[str, int] = Field(description="the busiest nodes")
    first_error: LogEntry | None = Field(description="ERROR or FATAL")
    last_error: LogEntry | None
    first_warning: LogEntry | None = Field(description="WARN or worse")
    bursts: list[BurstOut] = Field(description="many records within 1 s, most intense first")


class LogReport(BaseModel):
    bag: str
    topics: list[str]
    start: Instant
    end: Instant
    total: int = Field(description="records that match the filters")
    returned: int
    next_offset: int | None = Field(description="pass as offset for the next page")
    entries: list[LogEntry]
    summary: LogSummaryOut | None = Field(description="of the matching records")
    notes: list[str]
