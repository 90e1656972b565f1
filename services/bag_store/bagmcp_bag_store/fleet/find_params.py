"""The typed parameters of the fleet's two kinds of long work (query_bags, find_bags). ``readable`` is set by
the tool from the caller's token (the views it may read), never by the caller."""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, Field, field_validator

LogLevel = Literal["DEBUG", "INFO", "WARN", "ERROR", "FATAL"]


class QueryParams(BaseModel):
    sql: str
    readable: list[str]
    max_rows: int = Field(ge=1, le=1_000_000)


class FindParams(BaseModel):
    """find_bags' conditions (names kept short: a model reads them on every turn). ``topic`` is a topic the
    bag must have, and the topic whose gaps ``gap_above`` measures when both are given."""

    topic: str | None = None
    type: str | None = None
    between: list[float | str] | None = None
    log_level: LogLevel | None = None
    log_node: str | None = None
    log_text: str | None = None
    speed_above: float | None = Field(default=None, ge=0)
    near: list[float] | None = None
    scan_below: float | None = Field(default=None, gt=0)
    gap_above: float | None = Field(default=None, gt=0)
    limit: int = Field(default=50, ge=1, le=500)
    readable: list[str] = Field(default_factory=list)

    @field_validator("between")
    @classmethod
    def _from_and_to(cls, between: list[float | str] | None) -> list[float | str] | None:
        if between is not None and len(between) != 2:
            raise ValueError("between must be [from, to]: epoch seconds or ISO-8601, e.g. ['2026-11-01', '2026-11-08']")
        return between

    @field_validator("near")
    @classmethod
    def _point_and_radius(cls, near: list[float] | None) -> list[float] | None:
        if near is not None and (len(near) != 3 or near[2] <= 0):
            raise ValueError("near must be [x, y, radius] in metres with a radius above 0, e.g. [3, -1, 0.5]")
        return near
