"""Output schemas of the bag-store tools (MCP structured content). Times are ``Instant``s; the clock
is stated where a time could be read on more than one."""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, Field, JsonValue

from bagmcp_shared.timebase import Instant

Clock = Literal["log_time"]


class BagBrief(BaseModel):
    """``error`` says why a bag with status "failed" cannot be used."""

    id: str
    name: str
    status: str = Field(description="ready, ingesting or failed")
    error: str | None = None
    progress: float | None = Field(default=None, description="ingest progress 0..1 while ingesting")
    format: str | None
    size_bytes: int
    duration_s: float | None
    message_count: int | None
    topic_count: int | None
    start: Instant | None
    tags: list[str]


class BagList(BaseModel):
    bags: list[BagBrief]
    total: int
    offset: int
    next_offset: int | None


class TopicInfo(BaseModel):
    name: str
    type: str
    count: int
    rate_hz: float | None = Field(description="from log (receive) times")
    header_rate_hz: float | None = Field(default=None, description="from header stamps, where present and sane")
    first: Instant | None
    last: Instant | None
    note: str | None = Field(default=None, description="why a number here looks odd")


class BagInfo(BaseModel):
    id: str
    name: str
    status: str
    format: str
    size_bytes: int
    sha256: str
    message_count: int
    duration_s: float
    start: Instant | None
    end: Instant | None
    topics: list[TopicInfo]
    notes: list[str]


class FieldInfo(BaseModel):
    path: str
    type: str
    unit: str | None


class TopicDescription(BaseModel):
    bag: str
    topic: str
    type: str
    count: int
    rate_hz: float | None = Field(description="from log times")
    fields: list[FieldInfo]
    fields_truncated: bool
    sample: JsonValue
    sample_time: Instant | None


class MessageOut(BaseModel):
    time: Instant = Field(description="log time")
    header_stamp_s: float | None = Field(description="header.stamp, epoch s")
    data: JsonValue


class RangeMessage(BaseModel):
    offset_s: float = Field(description="log time, s from the bag start (time_base)")
    data: JsonValue


class MessageAtTime(BaseModel):
    bag: str
    topic: str
    requested: Instant
    clock: Clock
    delta_s: float = Field(description="message time minus requested time")
    message: MessageOut


class MessageRange(BaseModel):
    """``messages`` (layout messages), or ``t`` and ``columns`` (layout columns: one list per field)."""

    bag: str
    topic: str
    start: Instant
    end: Instant
    clock: Clock
    time_base: str = Field(description="what offset_s and t count from")
    total: int = Field(description="messages in the whole window")
    returned: int
    truncated: bool
    next_cursor: str | None
    messages: list[RangeMessage]
    t: list[float | int] | None = Field(default=None, description="s from bag start, to 1 ms (layout columns)")
    digits: int | None = Field(default=None, description="significant digits of the column values")
    columns: dict[str, list[float | int | None]] | None = Field(default=None, description="one list per field")
    downsampled: bool = Field(default=False, description="fewer points than messages; extremes kept")
    notes: list[str] = Field(default_factory=list)


class Correlated(BaseModel):
    """The message of another topic nearest in time to a match (within the tolerance)."""

    topic: str
    time: Instant
    delta_s: float = Field(description="its time minus the match's time")
    data: JsonValue


class SearchMatch(BaseModel):
    time: Instant
    value: JsonValue
    details: dict[str, JsonValue] | None = Field(default=None, description="for logs: level name, node, text")
    distance_m: float | None = None
    correlated: Correlated | None = None


class ClosestApproach(BaseModel):
    distance_m: float
    x: float = Field(description="m")
    y: float = Field(description="m")
    time: Instant


class SearchResult(BaseModel):
    bag: str
    topic: str
    condition: str
    field: str | None = Field(description="the message path tested")
    start: Instant
    end: Instant
    clock: Clock
    scanned: int = Field(description="messages in the window")
    total: int = Field(description="messages that match")
    returned: int
    truncated: bool
    matches: list[SearchMatch]
    closest: ClosestApproach | None
    source: Literal["index", "bag"]


class FilterResult(BaseModel):
    bag_id: str
    name: str
    format: str
    counts: dict[str, int] = Field(description="messages per topic")
    message_count: int
    created: bool = Field(description="false when the same bag existed already")
    note: str | None = Field(default=None, description="why the bag has another name than the one asked for")
