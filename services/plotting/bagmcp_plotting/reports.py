"""What every plotting tool answers next to the image: the artifact and what was plotted."""

from __future__ import annotations

from pydantic import BaseModel, Field, PrivateAttr

from bagmcp_shared.timebase import Instant


class Artifact(BaseModel):
    id: str
    url: str = Field(description="GET it with the same bearer token (REST)")
    mime_type: str
    bytes: int
    width: int = Field(description="pixels")
    height: int


class SeriesOut(BaseModel):
    name: str = Field(description="message path (or bag name in compare_runs)")
    unit: str | None
    points: int = Field(description="finite points read")
    min: float | None
    max: float | None


class PlotReport(BaseModel):
    bags: list[str]
    title: str
    start: Instant | None = Field(description="window plotted (of the first bag)")
    end: Instant | None
    series: list[SeriesOut]
    artifact: Artifact
    notes: list[str]
    _png: bytes | None = PrivateAttr(default=None)

    @property
    def png(self) -> bytes | None:
        """The image of a plot just drawn in this process (None once the report went through JSON): the
        answer shows these bytes rather than reading back from storage the object it has just written."""
        return self._png

    def with_png(self, png: bytes) -> PlotReport:
        drawn = self.model_copy()
        drawn._png = png
        return drawn
