"""get_image_at_time: the image nearest a time as a picture (raw encodings and compressed), sized to send, and
its params model (the tool is declared in tools/image_tools.py)."""

from __future__ import annotations

from typing import Annotated, Protocol, cast

import numpy as np
from pydantic import BaseModel, Field

from bagmcp_analysis.images import Picture, compressed_image, encode_picture, raw_image
from bagmcp_analysis.reports.images import ImageReport
from bagmcp_kit.arguments import BagRef, TimeArg
from bagmcp_shared.access import BagAccess
from bagmcp_shared.carry import carried
from bagmcp_shared.errors import ArgumentError
from bagmcp_shared.jobs import Progress
from bagmcp_shared.timebase import header_stamp_ns

RAW = "sensor_msgs/msg/Image"
COMPRESSED = "sensor_msgs/msg/CompressedImage"


class _Raw(Protocol):
    encoding: str
    width: int
    height: int
    step: int
    is_bigendian: int
    data: np.ndarray


class _Compressed(Protocol):
    format: str
    data: np.ndarray


def _picture(msgtype: str, message: object) -> tuple[Picture, str]:
    if msgtype == RAW:
        image = cast(_Raw, message)
        picture = raw_image(
            encoding=image.encoding,
            width=int(image.width),
            height=int(image.height),
            step=int(image.step),
            data=image.data,
            is_bigendian=bool(image.is_bigendian),
        )
        return picture, image.encoding
    compressed = cast(_Compressed, message)
    return compressed_image(format=compressed.format, data=compressed.data), compressed.format or "compressed"


class ImageParams(BaseModel):
    bag: BagRef
    topic: Annotated[str, Field(description="Image or CompressedImage topic")]
    time: TimeArg
    max_size: Annotated[int, Field(ge=16, le=4096, description="longest side in pixels")] = 1024


def get_image_at_time(access: BagAccess, params: ImageParams, progress: Progress) -> ImageReport:
    """The report, carrying the encoded picture (``ImageReport.picture``)."""
    with access.open(params.bag) as ob:
        name, msgtype = ob.topic_name(params.topic), ob.msgtype(params.topic)
        if msgtype not in (RAW, COMPRESSED):
            raise ArgumentError(f"{name} is {msgtype}; give a sensor_msgs/Image or CompressedImage topic")
        wanted = ob.time(params.time)
        raw = ob.nearest(name, wanted)
        message = ob.reader.decode(raw)
        try:
            picture, encoding = _picture(msgtype, message)
            encoded = encode_picture(picture, max_size=params.max_size)
        except ValueError as err:
            raise ArgumentError(f"{name} at {ob.instant(raw.log_time_ns).offset_s:.3f} s: {err}") from err
        header = header_stamp_ns(message)
        frame = getattr(getattr(message, "header", None), "frame_id", None)
        report = carried(
            ImageReport,
            picture,
            bag=ob.name,
            topic=name,
            type=msgtype,
            time=ob.instant(raw.log_time_ns),
            delta_s=(raw.log_time_ns - wanted) / 1e9,
            header_stamp_s=header / 1e9 if header else None,
            frame=str(frame) if frame else None,
            encoding=encoding,
            sent_width=encoded.width,
            sent_height=encoded.height,
            mime_type=encoded.mime_type,
        )
        return report.with_picture(encoded)
