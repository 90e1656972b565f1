"""Output schemas of the bag-store tools (MCP structured content)."""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, JsonValue

Clock = Literal["log_time"]


class Instant(BaseModel):
    """One instant: seconds from the bag start, absolute epoch seconds, ISO-8601 UTC."""

    offset_s: float
    stamp_s: float
    iso: str


class BagBrief(BaseModel):
    """``error`` says why a bag with status "failed" cannot be used."""

    id: str
    name: str
    status: str
    error: str | None = None
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
    """``rate_hz`` is from log (receive) times; ``header_rate_hz`` from header stamps where the type
    has them and they are sane (indexed types)."""

    name: str
    type: str
    count: int
    rate_hz: float | None
    header_rate_hz: float | None = None
    first: Instant | None
    last: Instant | None


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
    rate_hz: float | None
    fields: list[FieldInfo]
    fields_truncated: bool
    sample: JsonValue
    sample_time: Instant | None


class MessageOut(BaseModel):
    time: Instant
    header_stamp_s: float | None
    data: JsonValue


class MessageAtTime(BaseModel):
    bag: str
    topic: str
    requested: Instant
    clock: Clock
    delta_s: float
    message: MessageOut


class MessageRange(BaseModel):
    bag: str
    topic: str
    start: Instant
    end: Instant
    clock: Clock
    total: int
    returned: int
    truncated: bool
    next_cursor: str | None
    messages: list[MessageOut]


class Correlated(BaseModel):
    """The message of another topic nearest in time to a match (within the tolerance)."""

    topic: str
    time: Instant
    delta_s: float
    data: JsonValue


class SearchMatch(BaseModel):
    time: Instant
    value: JsonValue
    distance_m: float | None = None
    correlated: Correlated | None = None


class ClosestApproach(BaseModel):
    distance_m: float
    x: float
    y: float
    time: Instant


class SearchResult(BaseModel):
    bag: str
    topic: str
    condition: str
    field: str | None
    start: Instant
    end: Instant
    clock: Clock
    scanned: int
    total: int
    returned: int
    truncated: bool
    matches: list[SearchMatch]
    closest: ClosestApproach | None
    source: Literal["index", "bag"]


class JobInfo(BaseModel):
    """A job as get_job reports it; ``result`` is set once it succeeded."""

    job_id: str
    kind: str
    state: str
    progress: float
    message: str
    error: str | None
    result: JsonValue
    created_at: float
    updated_at: float


class SearchAnswer(BaseModel):
    """``result`` when the search finished within the time budget; otherwise follow ``job``."""

    job: JobInfo
    result: SearchResult | None


class FilterResult(BaseModel):
    bag_id: str
    name: str
    format: str
    counts: dict[str, int]
    message_count: int
    created: bool


class FilterAnswer(BaseModel):
    """``result`` when the new bag was written within the time budget; otherwise follow ``job``."""

    job: JobInfo
    result: FilterResult | None
