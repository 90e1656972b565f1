"""MCP adapter for get_image_at_time: the picture as image content, with its metadata."""

from __future__ import annotations

import base64
from typing import Annotated

import anyio
from mcp.types import CallToolResult, ImageContent
from pydantic import Field

from bagmcp_analysis.queries.images import get_image_at_time
from bagmcp_analysis.reports.images import ImageReport
from bagmcp_kit.answers import answer, tool_errors
from bagmcp_kit.arguments import READ_ONLY, BagRef, TimeArg
from bagmcp_kit.toolsets import tool
from bagmcp_shared.access import BagAccess


class ImageTools:
    def __init__(self, access: BagAccess) -> None:
        self._access = access

    @tool(READ_ONLY)
    async def get_image_at_time(
        self,
        bag: BagRef,
        topic: Annotated[str, Field(description="Image or CompressedImage topic")],
        time: TimeArg,
        max_size: Annotated[int, Field(ge=16, le=4096, description="longest side in pixels")] = 1024,
    ) -> Annotated[CallToolResult, ImageReport]:
        """The camera image nearest a time, as an image you can see (raw, Bayer, YUV, depth in colour, JPEG,
        PNG), with its stamp, encoding and size. Example: topic="/camera/image_raw", time=3."""
        with tool_errors():
            report, encoded = await anyio.to_thread.run_sync(
                lambda: get_image_at_time(self._access, bag, topic, time, max_size=max_size)
            )
        picture = ImageContent(type="image", data=base64.b64encode(encoded.data).decode(), mime_type=encoded.mime_type)
        summary = (
            f"{report.topic} at {report.time.offset_s:.3f} s: {report.encoding} {report.width}x{report.height}"
            f" sent as {report.mime_type} {report.sent_width}x{report.sent_height}"
        )
        return answer(report, summary, extra=[picture])
