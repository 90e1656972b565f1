"""The typed parameters of the fleet's two kinds of long work (query_bags, find_bags), in the order the tools list
them. ``readable`` is set by the server from the caller's token (the views it may read), never by the caller;
fields marked ``GIVEN`` are no arguments."""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import BaseModel, Field, field_validator

from bagmcp_kit.declared import GIVEN

LogLevel = Literal["DEBUG", "INFO", "WARN", "ERROR", "FATAL"]


class QueryParams(BaseModel):
    sql: Annotated[str, Field(description="one SELECT")]
    readable: Annotated[list[str], GIVEN]
    max_rows: Annotated[int, GIVEN, Field(ge=1, le=1_000_000)]


class FindParams(BaseModel):
    """find_bags' conditions (names kept short: a model reads them on every turn). ``topic`` is a topic the
    bag must have, and the topic whose gaps ``gap_above`` measures when both are given."""

    topic: Annotated[str | None, Field(description="has it")] = None
    type: Annotated[str | None, Field(description="has one")] = None
    between: Annotated[list[float | str] | None, Field(description="recorded: [from, to] epoch s/ISO")] = None
    log_level: Annotated[LogLevel | None, Field(description="at or above")] = None
    log_node: Annotated[str | None, Field(description="part")] = None
    log_text: Annotated[str | None, Field(description="part")] = None
    speed_above: Annotated[float | None, Field(ge=0, description="m/s")] = None
    near: Annotated[list[float] | None, Field(description="[x, y, radius] m")] = None
    scan_below: Annotated[float | None, Field(gt=0, description="m")] = None
    gap_above: Annotated[float | None, Field(gt=0, description="s")] = None
    limit: Annotated[int, GIVEN, Field(ge=1, le=500)] = 50
    readable: Annotated[list[str], GIVEN] = Field(default_factory=list)

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
