"""ROS camera images turned into pictures an agent can look at.

raw_image decodes sensor_msgs/Image fields (colour, mono, 8- and 16-bit Bayer, YUV 4:2:2 and depth encodings),
compressed_image decodes sensor_msgs/CompressedImage (JPEG/PNG and compressedDepth), both into a Picture
(RGB or grey pixels; depth colourised with turbo). encode_picture scales a Picture down and encodes it
as JPEG or PNG.

Memory: an image is decoded only when its pixels fit the process's image budget
(``BAGMCP_MAX_IMAGE_BYTES``, checked on the header's width and height before a pixel is decoded), and
depth, Bayer and YUV images are converted in blocks of rows, in their own pixel type; a 199 KB
compressedDepth PNG of 9500 x 9500 made one call peak at 4.4 GB when the whole image went through float64.
"""

from __future__ import annotations

import functools
import io
import struct
from dataclasses import dataclass
from typing import Literal, TypeVar

import numpy as np
import numpy.typing as npt
from PIL import Image

from bagmcp_shared.budget import check_image

PictureKind = Literal["color", "mono", "depth"]
_Scalar = TypeVar("_Scalar", bound=np.generic)

_COLOR_8BIT: dict[str, tuple[int, tuple[int, int, int]]] = {
    "rgb8": (3, (0, 1, 2)),
    "bgr8": (3, (2, 1, 0)),
    "8uc3": (3, (2, 1, 0)),
    "rgba8": (4, (0, 1, 2)),
    "bgra8": (4, (2, 1, 0)),
    "8uc4": (4, (2, 1, 0)),
}
_MONO_8BIT = frozenset({"mono8", "8uc1"})
_DEPTH: dict[str, tuple[str, int, str]] = {
    "16uc1": ("u2", 2, "mm"),
    "mono16": ("u2", 2, "raw"),
    "32fc1": ("f4", 4, "m"),
}
# encoding -> (colour filter pattern, bytes per site)
_BAYER = {
    f"bayer_{pattern}{bits}": (pattern, bits // 8) for pattern in ("rggb", "bggr", "gbrg", "grbg") for bits in (8, 16)
}
# Byte offsets of (Y0, U, Y1, V) inside each 4-byte group that holds two pixels.
_YUV422 = {"yuv422": (1, 0, 3, 2), "uyvy": (1, 0, 3, 2), "yuv422_yuy2": (0, 1, 2, 3), "yuyv": (0, 1, 2, 3)}

_PNG_MAGIC = b"\x89PNG\r\n\x1a\n"
_DEPTH_HEADER = struct.Struct("<iff")  # compressed_depth_image_transport ConfigHeader: format, quant A, quant B
_BAYER_RB_KERNEL = np.array([[1.0, 2.0, 1.0], [2.0, 4.0, 2.0], [1.0, 2.0, 1.0]])
_BAYER_G_KERNEL = np.array([[0.0, 1.0, 0.0], [1.0, 4.0, 1.0], [0.0, 1.0, 0.0]])
_BLOCK_PIXELS = 1 << 20  # converted at a time: Bayer's float64 work is about 100 bytes a pixel, so ~100 MB
_PIL_BYTES = {"I;16": 2, "I;16B": 2, "I;16L": 2, "I;16N": 2, "I": 4, "F": 4}


@dataclass(frozen=True)
class DepthRange:
    """Valid values of a depth image in source units ("m", "mm" or "raw"); None when no pixel is valid."""

    min_value: float | None
    max_value: float | None
    unit: str
    valid_fraction: float


@dataclass(frozen=True, eq=False)
class Picture:
    """Decoded image: pixels are HxWx3 RGB or HxW grey uint8; width/height are the original size."""

    pixels: npt.NDArray[np.uint8]
    source_encoding: str
    width: int
    height: int
    kind: PictureKind
    depth: DepthRange | None = None


@dataclass(frozen=True)
class Encoded:
    """An encoded picture ready to send: bytes, MIME type and the size as sent."""

    data: bytes
    mime_type: str
    width: int
    height: int


def raw_image(
    *, encoding: str, width: int, height: int, step: int, data: bytes | npt.NDArray[np.uint8], is_bigendian: bool
) -> Picture:
    """Decode the fields of a sensor_msgs/Image; raises ValueError for unknown encodings or short data."""
    key = encoding.strip().lower()
    if (native := _native_bytes(key)) is not None:
        picture_bytes = 1 if key in _MONO_8BIT else 3
        check_image(f"the {encoding} image", width=width, height=height, bytes_per_pixel=max(native, picture_bytes))
    buf = _byte_array(data)
    if key in _COLOR_8BIT:
        channels, order = _COLOR_8BIT[key]
        rows = _rows(buf, encoding=encoding, width=width, height=height, step=step, row_bytes=width * channels)
        rgb = rows.reshape(height, width, channels)[:, :, list(order)]
        return _picture(rgb, encoding=encoding, kind="color")
    if key in _MONO_8BIT:
        grey = _rows(buf, encoding=encoding, width=width, height=height, step=step, row_bytes=width)
        return _picture(grey, encoding=encoding, kind="mono")
    if key in _DEPTH:
        dtype, size, unit = _DEPTH[key]
        rows = _rows(buf, encoding=encoding, width=width, height=height, step=step, row_bytes=width * size)
        values = np.ascontiguousarray(rows).view((">" if is_bigendian else "<") + dtype).reshape(height, width)
        return _depth_picture(values, encoding=encoding, unit=unit)
    if key in _BAYER:
        pattern, size = _BAYER[key]
        rows = _rows(buf, encoding=encoding, width=width, height=height, step=step, row_bytes=width * size)
        dtype = "u1" if size == 1 else (">" if is_bigendian else "<") + "u2"
        mosaic = np.ascontiguousarray(rows).view(dtype).reshape(height, width)
        full_scale = float(np.iinfo(np.dtype(dtype)).max)
        return _picture(
            _demosaic_blocks(mosaic, pattern=pattern, full_scale=full_scale), encoding=encoding, kind="color"
        )
    if key in _YUV422:
        if width % 2:
            raise ValueError(f"A {encoding} image must have an even width, but this one is {width} pixels wide.")
        rows = _rows(buf, encoding=encoding, width=width, height=height, step=step, row_bytes=width * 2)
        rgb = np.concatenate([_yuv422_to_rgb(block, offsets=_YUV422[key]) for block in _row_blocks(rows)])
        return _picture(rgb, encoding=encoding, kind="color")
    names = [*_COLOR_8BIT, *sorted(_MONO_8BIT), *_DEPTH, *_BAYER, *_YUV422]
    known = ", ".join(name.upper() if name[0].isdigit() else name for name in names)
    raise ValueError(f"The image encoding {encoding!r} is not supported; supported encodings are: {known}.")


def compressed_image(*, format: str, data: bytes | npt.NDArray[np.uint8]) -> Picture:
    """Decode a sensor_msgs/CompressedImage (JPEG/PNG, compressedDepth PNG); ValueError if it cannot be decoded."""
    raw = data.tobytes() if isinstance(data, np.ndarray) else bytes(data)
    leading = format.split(";")[0].strip().lower()
    error: Exception | None = None
    for payload, quant in _payload_candidates(raw):
        try:
            image = Image.open(io.BytesIO(payload))  # reads the header only
        except (OSError, SyntaxError, ValueError, Image.DecompressionBombError) as exc:
            error = exc
            continue
        with image:
            native = _PIL_BYTES.get(image.mode, len(image.getbands()))
            check_image(
                f"the {format or 'compressed'} image",
                width=image.width,
                height=image.height,
                bytes_per_pixel=max(native, 3),
            )
            try:
                image.load()
                return _picture_from_pil(image, fmt=format, leading=leading, quant=quant)
            except (OSError, SyntaxError, ValueError, Image.DecompressionBombError) as exc:
                error = exc
    raise ValueError(
        f"the compressed image could not be decoded ({error}); the format is {format!r} and the data has "
        f"{len(raw)} bytes. Check that the topic really carries JPEG or PNG data."
    )


def encode_picture(picture: Picture, *, max_size: int = 1024) -> Encoded:
    """Scale down so the longest side is <= max_size (never up); JPEG q85 for large colour, PNG otherwise."""
    if max_size < 1:
        raise ValueError(f"max_size must be at least 1 pixel, not {max_size}.")
    image = Image.fromarray(np.ascontiguousarray(picture.pixels))
    longest = max(image.width, image.height)
    if longest > max_size:
        scale = max_size / longest
        size = (max(1, round(image.width * scale)), max(1, round(image.height * scale)))
        image = image.resize(size, Image.Resampling.LANCZOS)
    out = io.BytesIO()
    if picture.kind == "color" and image.width * image.height > 256 * 256:
        image.save(out, format="JPEG", quality=85)
        mime_type = "image/jpeg"
    else:
        image.save(out, format="PNG")
        mime_type = "image/png"
    return Encoded(data=out.getvalue(), mime_type=mime_type, width=image.width, height=image.height)


def _byte_array(data: bytes | npt.NDArray[np.uint8]) -> npt.NDArray[np.uint8]:
    if isinstance(data, np.ndarray):
        return np.ascontiguousarray(data).reshape(-1).view(np.uint8)
    return np.frombuffer(data, dtype=np.uint8)


def _rows(
    buf: npt.NDArray[np.uint8], *, encoding: str, width: int, height: int, step: int, row_bytes: int
) -> npt.NDArray[np.uint8]:
    """The height x row_bytes pixel bytes, skipping the row padding that step allows."""
    if width <= 0 or height <= 0:
        raise ValueError(f"The {encoding} image is empty ({width}x{height}); pick a message with pixels.")
    if step < row_bytes:
        raise ValueError(f"The {encoding} image has step {step} but {width} pixels need {row_bytes} bytes per row.")
    needed = step * (height - 1) + row_bytes
    if buf.size < needed:
        raise ValueError(
            f"The {encoding} image of {width}x{height} with step {step} needs {step * height} bytes "
            f"(at least {needed}), but the message has only {buf.size}."
        )
    if buf.size < step * height:
        buf = np.concatenate([buf[:needed], np.zeros(step * height - needed, dtype=np.uint8)])
    return buf[: step * height].reshape(height, step)[:, :row_bytes]


def _picture(
    pixels: npt.NDArray[np.uint8], *, encoding: str, kind: PictureKind, depth: DepthRange | None = None
) -> Picture:
    frozen = np.array(pixels, dtype=np.uint8, copy=True)
    frozen.flags.writeable = False
    height, width = frozen.shape[:2]
    return Picture(pixels=frozen, source_encoding=encoding, width=width, height=height, kind=kind, depth=depth)


@functools.cache
def _turbo_table() -> npt.NDArray[np.uint8]:
    """The turbo colormap for depth images; matplotlib is imported here, on the first depth image, not when
    the service starts (about 0.3 s of every analysis process's start)."""
    import matplotlib

    rgba = matplotlib.colormaps["turbo"](np.linspace(0.0, 1.0, 256), bytes=True)
    return np.asarray(rgba, dtype=np.uint8)[:, :3]


def _native_bytes(key: str) -> int | None:
    """Bytes per pixel of a raw encoding as stored; None for an encoding this module does not decode."""
    if key in _COLOR_8BIT:
        return _COLOR_8BIT[key][0]
    if key in _MONO_8BIT:
        return 1
    if key in _DEPTH:
        return _DEPTH[key][1]
    if key in _BAYER:
        return _BAYER[key][1]
    return 2 if key in _YUV422 else None


def _row_blocks(values: npt.NDArray[_Scalar]) -> list[npt.NDArray[_Scalar]]:
    """Views of consecutive rows of about ``_BLOCK_PIXELS`` each (no copies)."""
    rows = max(1, _BLOCK_PIXELS // max(1, values.shape[1]))
    return [values[start : start + rows] for start in range(0, values.shape[0], rows)]


def _valid(block: npt.NDArray[np.generic]) -> npt.NDArray[np.bool_]:
    return np.asarray(np.isfinite(block) & (block != 0))


def _valid_range(values: npt.NDArray[np.generic]) -> tuple[float, float, int] | None:
    """(min, max, count) of the valid values (not 0, NaN or inf), block by block; None when there are none."""
    low, high, count = np.inf, -np.inf, 0
    for block in _row_blocks(values):
        good = block[_valid(block)]
        if good.size:
            low, high, count = min(low, float(good.min())), max(high, float(good.max())), count + good.size
    return (low, high, count) if count else None


def _depth_picture(values: npt.NDArray[np.generic], *, encoding: str, unit: str) -> Picture:
    """Turbo-coloured depth: invalid values (0, NaN, inf) black, valid ones spread over [min, max]; the values
    stay in their own type, and only a block of rows at a time is widened to float64."""
    pixels = np.zeros((*values.shape, 3), dtype=np.uint8)
    found = _valid_range(values)
    if found is None:
        depth = DepthRange(min_value=None, max_value=None, unit=unit, valid_fraction=0.0)
        return _picture(pixels, encoding=encoding, kind="depth", depth=depth)
    low, high, count = found
    for block, out in zip(_row_blocks(values), _row_blocks(pixels), strict=True):
        valid = _valid(block)
        good = block[valid].astype(np.float64)
        norm = (good - low) / (high - low) if high > low else np.full(good.shape, 0.5)
        out[valid] = _turbo_table()[np.rint(norm * 255).astype(np.intp)]
    depth = DepthRange(min_value=low, max_value=high, unit=unit, valid_fraction=count / values.size)
    return _picture(pixels, encoding=encoding, kind="depth", depth=depth)


def _convolve3x3(image: npt.NDArray[np.float64], kernel: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    height, width = image.shape
    padded = np.pad(image, 1)
    out = np.zeros_like(image)
    for dy in range(3):
        for dx in range(3):
            if kernel[dy, dx]:
                out += kernel[dy, dx] * padded[dy : dy + height, dx : dx + width]
    return out


def _demosaic_blocks(mosaic: npt.NDArray[np.generic], *, pattern: str, full_scale: float) -> npt.NDArray[np.uint8]:
    """:func:`_demosaic` a block of rows at a time, each with its neighbouring rows (so blocks join exactly)."""
    height = mosaic.shape[0]
    out = np.empty((*mosaic.shape, 3), dtype=np.uint8)
    step = max(1, _BLOCK_PIXELS // max(1, mosaic.shape[1]))
    for start in range(0, height, step):
        stop = min(height, start + step)
        lo, hi = max(0, start - 1), min(height, stop + 1)
        slab = _demosaic(mosaic[lo:hi].astype(np.float64), pattern=pattern, full_scale=full_scale, first_row=lo)
        out[start:stop] = slab[start - lo : stop - lo]
    return out


def _demosaic(
    mosaic: npt.NDArray[np.float64], *, pattern: str, full_scale: float, first_row: int = 0
) -> npt.NDArray[np.uint8]:
    """Bilinear demosaic as a normalised convolution (exact for uniform colours, also at the borders), with
    ``full_scale`` (255 or 65535) shown as 255; ``first_row`` is where these rows start in the image (the
    colour filter's phase)."""
    height, width = mosaic.shape
    rows, cols = np.indices((height, width))
    rows += first_row
    site = np.array(list(pattern))[(rows % 2) * 2 + cols % 2]
    raw = mosaic * (255.0 / full_scale)
    channels: list[npt.NDArray[np.float64]] = []
    for name in "rgb":
        mask = (site == name).astype(np.float64)
        kernel = _BAYER_G_KERNEL if name == "g" else _BAYER_RB_KERNEL
        weight = _convolve3x3(mask, kernel)
        total = _convolve3x3(raw * mask, kernel)
        channels.append(np.divide(total, weight, out=np.zeros_like(total), where=weight > 0))
    return np.clip(np.rint(np.stack(channels, axis=-1)), 0, 255).astype(np.uint8)


def _yuv422_to_rgb(rows: npt.NDArray[np.uint8], *, offsets: tuple[int, int, int, int]) -> npt.NDArray[np.uint8]:
    """BT.601 limited-range (studio swing) YUV 4:2:2 to RGB, as OpenCV/cv_bridge convert it."""
    height = rows.shape[0]
    groups = rows.reshape(height, -1, 4).astype(np.float64)
    y0, u, y1, v = (groups[:, :, k] for k in offsets)
    luma = 1.164 * (np.stack([y0, y1], axis=-1).reshape(height, -1) - 16.0)
    cb = np.repeat(u, 2, axis=1) - 128.0
    cr = np.repeat(v, 2, axis=1) - 128.0
    rgb = np.stack([luma + 1.596 * cr, luma - 0.813 * cr - 0.391 * cb, luma + 2.018 * cb], axis=-1)
    return np.clip(np.rint(rgb), 0, 255).astype(np.uint8)


def _payload_candidates(raw: bytes) -> list[tuple[bytes, tuple[float, float] | None]]:
    """Image bytes to try, with compressedDepth quantisation when the 12-byte header precedes a PNG."""
    if raw[12:20] == _PNG_MAGIC and not raw.startswith(_PNG_MAGIC):
        _, quant_a, quant_b = _DEPTH_HEADER.unpack(raw[:12])
        return [(raw[12:], (quant_a, quant_b)), (raw, None)]
    return [(raw, None)]


def _picture_from_pil(image: Image.Image, *, fmt: str, leading: str, quant: tuple[float, float] | None) -> Picture:
    if image.mode.startswith("I") or image.mode == "F":
        values: npt.NDArray[np.generic] = np.asarray(image)
        unit = _DEPTH[leading][2] if leading in _DEPTH else "raw"
        if leading == "32fc1" and quant is not None and quant[0] != 0:
            values = _dequantise(values.astype(np.float32), quant)
        return _depth_picture(values, encoding=fmt, unit=unit)
    if image.mode in ("L", "LA", "1"):
        return _picture(np.asarray(image.convert("L"), dtype=np.uint8), encoding=fmt, kind="mono")
    return _picture(np.asarray(image.convert("RGB"), dtype=np.uint8), encoding=fmt, kind="color")


def _dequantise(inverse: npt.NDArray[np.float32], quant: tuple[float, float]) -> npt.NDArray[np.float32]:
    """compressedDepth 32FC1: depth = A / (value - B); value 0 means no measurement."""
    quant_a, quant_b = quant
    with np.errstate(divide="ignore", invalid="ignore"):
        depth = quant_a / (inverse - quant_b)
    return np.where(inverse == 0, np.nan, depth)
