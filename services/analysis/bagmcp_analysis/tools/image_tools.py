"""The declaration of get_image_at_time (a short tool): the picture as image content, beside its metadata; its
params model lives beside its query in queries/images.py."""

from __future__ import annotations

import base64

from mcp.types import ContentBlock, ImageContent

from bagmcp_analysis.queries.images import ImageParams, get_image_at_time
from bagmcp_analysis.reports.images import ImageReport
from bagmcp_kit.declared import Declared
from bagmcp_shared.access import BagAccess


def _summary(report: ImageReport) -> str:
    return (
        f"{report.topic} at {report.time.offset_s:.3f} s: {report.encoding} {report.width}x{report.height}"
        f" sent as {report.mime_type} {report.sent_width}x{report.sent_height}"
    )


def _picture(access: BagAccess, report: ImageReport) -> list[ContentBlock]:
    encoded = report.picture
    assert encoded is not None  # the query always carries it; a report read back from JSON never gets here
    return [ImageContent(type="image", data=base64.b64encode(encoded.data).decode(), mime_type=encoded.mime_type)]


IMAGE = Declared[BagAccess, ImageParams, ImageReport](
    "get_image_at_time",
    "The camera image nearest a time, as an image you can see (raw, Bayer, YUV, depth in colour, JPEG, PNG), "
    'with its stamp, encoding and size. Example: topic="/camera/image_raw", time=3.',
    ImageParams,
    ImageReport,
    get_image_at_time,
    _summary,
    long=False,
    attach=_picture,
)
