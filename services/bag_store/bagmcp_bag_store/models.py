"""The catalog record of a bag."""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, Field, JsonValue

BagStatus = Literal["ingesting", "ready", "failed"]


class BagRecord(BaseModel):
    """What the catalog knows about one bag.

    ``files`` are the bag's files relative to its root: one name for a single-file bag, the
    storage files and metadata.yaml for a ROS 2 directory (``layout == "directory"``).
    ``source`` is where the files live: an object-key prefix (``bags/<id>``) when ``in_store``,
    else a path relative to the folder an embedded server serves (read-only).
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
    created_at: float
    tags: list[str] = Field(default_factory=list)
    summary: dict[str, JsonValue] | None = None
    index_files: list[str] = Field(default_factory=list)

    def summary_value(self, key: str) -> JsonValue:
        return self.summary.get(key) if self.summary else None
