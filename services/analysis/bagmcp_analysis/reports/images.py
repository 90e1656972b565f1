"""What get_image_at_time answers next to the picture itself (which the report carries outside its JSON)."""

from __future__ import annotations

from pydantic import BaseModel, Field, PrivateAttr

from bagmcp_analysis.images import DepthRange, Encoded
from bagmcp_shared.timebase import Instant


class ImageReport(BaseModel):
    bag: str
    topic: str
    type: str
    time: Instant = Field(description="log time of the image shown")
    delta_s: float = Field(description="image time minus requested time")
    header_stamp_s: float | None = Field(description="epoch s")
    frame: str | None
    encoding: str = Field(description="raw encoding, or the compressed format")
    width: int = Field(description="original pixels")
    height: int
    sent_width: int
    sent_height: int
    mime_type: str
    kind: str = Field(description="color, mono or depth")
    depth: DepthRange | None = Field(description="range of valid depth values (depth images)")
    _picture: Encoded | None = PrivateAttr(default=None)

    @property
    def picture(self) -> Encoded | None:
        """The encoded image, shown as image content beside the report (None once it went through JSON)."""
        return self._picture

    def with_picture(self, picture: Encoded) -> ImageReport:
        shown = self.model_copy()
        shown._picture = picture
        return shown
