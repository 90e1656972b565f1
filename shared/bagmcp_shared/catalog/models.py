"""What the catalog knows about a bag: its record, and the summary ingest writes into it."""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, Field

from bagmcp_shared.bags import BagSummary
from bagmcp_shared.carry import carried

BagStatus = Literal["ingesting", "ready", "failed"]


class TopicStats(BaseModel):
    """One topic as ingest found it; times are epoch nanoseconds of the log (receive) clock."""

    name: str
    type: str
    count: int
    first_ns: int | None
    last_ns: int | None
    rate_hz: float | None
    header_rate_hz: float | None = None


class CatalogSummary(BaseModel):
    """A bag's summary as ingest stores it (and ``bagmcp info --json`` prints it)."""

    format: str
    profile: str = ""
    files: list[str]
    size_bytes: int
    message_count: int
    start_ns: int | None
    end_ns: int | None
    duration_s: float
    topics: list[TopicStats]
    notes: list[str] = Field(default_factory=list)

    @classmethod
    def of(cls, summary: BagSummary, *, header_rates: dict[str, float] | None = None) -> CatalogSummary:
        rates = header_rates or {}
        topics = [
            carried(
                TopicStats,
                t,
                type=t.msgtype,
                rate_hz=round(t.rate_hz, 4) if t.rate_hz is not None else None,
                header_rate_hz=rates.get(t.name),
            )
            for t in summary.topics
        ]
        return carried(
            cls,
            summary,
            format=str(summary.format),
            files=list(summary.files),
            duration_s=round(summary.duration_s, 9),
            topics=topics,
            notes=list(summary.notes),
        )

    def topic(self, name: str) -> TopicStats | None:
        """The topic called ``name``; a leading slash is optional on either side."""
        wanted = name.lstrip("/")
        return next((t for t in self.topics if t.name.lstrip("/") == wanted), None)


class BagRecord(BaseModel):
    """What the catalog knows about one bag.

    ``files`` are the bag's files relative to its root: one name for a single-file bag, the
    storage files and metadata.yaml for a ROS 2 directory (``layout == "directory"``).
    ``source`` is where the files live: an object-key prefix (``bags/<id>``) when ``in_store``,
    else a path relative to the folder an embedded server serves (read-only). ``etags`` are the
    object store's ETags of the files as stored (none in embedded mode or for bags stored before they
    were recorded): a range read of an object whose ETag differs is refused, never answered.
    ``file_sizes`` are each stored file's bytes (a directory's too, so a reader knows where each file ends
    before its first read; none for bags stored before they were recorded).
    """

    id: str
    name: str
    layout: Literal["file", "directory"]
    files: list[str]
    source: str
    in_store: bool
    sha256: str
    size_bytes: int
    status: BagStatus = "ingesting"
    error: str | None = None
    progress: float | None = None
    created_at: float
    ingest_queued_at: float | None = None  # when its ingest was last queued again (created_at before that)
    tags: list[str] = Field(default_factory=list)
    summary: CatalogSummary | None = None
    index_files: list[str] = Field(default_factory=list)
    etags: dict[str, str] = Field(default_factory=dict)
    file_sizes: dict[str, int] = Field(default_factory=dict)
