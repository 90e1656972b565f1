"""What get_tf_tree and lookup_transform answer."""

from __future__ import annotations

from pydantic import BaseModel, Field

from bagmcp_shared.timebase import Instant


class EdgeOut(BaseModel):
    parent: str
    child: str
    static: bool
    count: int
    rate_hz: float | None
    first: Instant
    last: Instant
    nearest: Instant | None = Field(description="sample nearest the requested time")


class TfTreeReport(BaseModel):
    bag: str
    topics: list[str]
    time: Instant | None = Field(description="the tree at this time (None: the whole bag)")
    frames: list[str] = Field(description="parents before children")
    roots: list[str]
    edges: list[EdgeOut]
    multiple_parents: dict[str, list[str]] = Field(description="frames published under more than one parent")
    notes: list[str]


class TransformReport(BaseModel):
    """T_target_source: maps a point in the source frame into the target frame (tf2's lookupTransform)."""

    bag: str
    target_frame: str
    source_frame: str
    time: Instant
    translation_m: list[float] = Field(description="x, y, z")
    rotation: list[float] = Field(description="quaternion x, y, z, w")
    roll_deg: float
    pitch_deg: float
    yaw_deg: float
    chain: list[str] = Field(description="frames from source to target")
    interpolated: bool
    extrapolated_s: float = Field(description="how far the time lies outside an edge's samples")
