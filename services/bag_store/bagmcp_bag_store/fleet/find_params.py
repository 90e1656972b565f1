"""The typed parameters of the fleet's two kinds of long work (query_bags, find_bags). ``readable`` is set by
the tool from the caller's token (the views it may read), never by the caller."""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, Field

LogLevel = Literal["DEBUG", "INFO", "WARN", "ERROR", "FATAL"]


class Near(BaseModel):
    x: float = Field(description="m, in the pose topic's frame")
    y: float = Field(description="m")
    radius_m: float = Field(gt=0, le=1e6)


class QueryParams(BaseModel):
    sql: str
    readable: list[str]
    max_rows: int = Field(ge=1, le=1_000_000)


class FindParams(BaseModel):
    has_topic: str | None = None
    has_type: str | None = None
    recorded_after: float | str | None = None
    recorded_before: float | str | None = None
    log_level: LogLevel | None = None
    log_node: str | None = None
    log_text: str | None = None
    speed_above_mps: float | None = Field(default=None, ge=0)
    near: Near | None = None
    scan_below_m: float | None = Field(default=None, gt=0)
    gap_longer_than_s: float | None = Field(default=None, gt=0)
    gap_topic: str | None = None
    limit: int = Field(default=50, ge=1, le=500)
    readable: list[str] = Field(default_factory=list)
