"""Tests for bagmcp_analysis.images: raw and compressed images decoded to known pixels, and re-encoding."""

from __future__ import annotations

import io
import struct

import matplotlib
import numpy as np
import numpy.typing as npt
import pytest
from PIL import Image

from bagmcp_analysis.images import Encoded, Picture, compressed_image, encode_picture, raw_image

# 4 wide x 3 high, every pixel a different colour.
RGB = np.array(
    [
        [[255, 0, 0], [0, 255, 0], [0, 0, 255], [255, 255, 0]],
        [[0, 255, 255], [255, 0, 255], [10, 20, 30], [40, 50, 60]],
        [[70, 80, 90], [100, 110, 120], [130, 140, 150], [0, 0, 0]],
    ],
    dtype=np.uint8,
)


def turbo(fraction: float) -> npt.NDArray[np.uint8]:
    rgba = matplotlib.colormaps["turbo"](fraction, bytes=True)
    return np.asarray(rgba, dtype=np.uint8)[:3]


@pytest.mark.parametrize(
    ("encoding", "pixels"),
    [
        ("rgb8", RGB),
        ("bgr8", RGB[:, :, ::-1]),
        ("8UC3", RGB[:, :, ::-1]),
        ("rgba8", np.dstack([RGB, np.full((3, 4), 7, dtype=np.uint8)])),
        ("bgra8", np.dstack([RGB[:, :, ::-1], np.full((3, 4), 7, dtype=np.uint8)])),
    ],
)
def test_colour_encodings_give_the_exact_rgb_pixels(encoding: str, pixels: npt.NDArray[np.uint8]) -> None:
    channels = pixels.shape[2]
    picture = raw_image(
        encoding=encoding, width=4, height=3, step=4 * channels, data=pixels.tobytes(), is_bigendian=False
    )
    assert picture.kind == "color"
    assert (picture.width, picture.height) == (4, 3)
    np.testing.assert_array_equal(picture.pixels, RGB)


@pytest.mark.parametrize("encoding", ["mono8", "8UC1"])
def test_mono_encodings_give_grey_pixels(encoding: str) -> None:
    grey = np.arange(12, dtype=np.uint8).reshape(3, 4) * 20
    picture = raw_image(encoding=encoding, width=4, height=3, step=4, data=grey, is_bigendian=False)
    assert picture.kind == "mono"
    assert picture.depth is None
    np.testing.assert_array_equal(picture.pixels, grey)


def test_row_padding_from_step_is_skipped() -> None:
    padded = np.full((3, 4 * 3 + 5), 0xAB, dtype=np.uint8)
    padded[:, :12] = RGB.reshape(3, 12)
    picture = raw_image(encoding="rgb8", width=4, height=3, step=17, data=padded.tobytes(), is_bigendian=False)
    np.testing.assert_array_equal(picture.pixels, RGB)


def test_last_row_padding_may_be_missing() -> None:
    padded = np.full((3, 6), 0xAB, dtype=np.uint8)
    padded[:, :4] = np.arange(12, dtype=np.uint8).reshape(3, 4)
    picture = raw_image(encoding="mono8", width=4, height=3, step=6, data=padded.tobytes()[:-2], is_bigendian=False)
    np.testing.assert_array_equal(picture.pixels, np.arange(12).reshape(3, 4))


@pytest.mark.parametrize("is_bigendian", [False, True])
def test_16uc1_depth_range_is_in_millimetres_with_zero_black(is_bigendian: bool) -> None:
    depth_mm = np.array([[0, 1000, 2000], [3000, 0, 5000]], dtype=np.uint16)
    data = depth_mm.astype(">u2" if is_bigendian else "<u2").tobytes()
    picture = raw_image(encoding="16UC1", width=3, height=2, step=6, data=data, is_bigendian=is_bigendian)
    assert picture.kind == "depth"
    assert picture.depth is not None
    assert picture.depth.unit == "mm"
    assert (picture.depth.min_value, picture.depth.max_value) == (1000.0, 5000.0)
    assert picture.depth.valid_fraction == pytest.approx(4 / 6)
    np.testing.assert_array_equal(picture.pixels[0, 0], [0, 0, 0])
    np.testing.assert_array_equal(picture.pixels[1, 1], [0, 0, 0])
    np.testing.assert_array_equal(picture.pixels[0, 1], turbo(0.0))
    np.testing.assert_array_equal(picture.pixels[1, 2], turbo(1.0))
    np.testing.assert_array_equal(picture.pixels[0, 2], turbo(0.25))


def test_32fc1_nan_and_inf_are_invalid_and_range_is_in_metres() -> None:
    depth_m = np.array([[np.nan, 0.5, 1.5], [np.inf, 2.5, 0.0]], dtype="<f4")
    picture = raw_image(encoding="32FC1", width=3, height=2, step=12, data=depth_m.tobytes(), is_bigendian=False)
    assert picture.depth is not None
    assert picture.depth.unit == "m"
    assert (picture.depth.min_value, picture.depth.max_value) == (0.5, 2.5)
    assert picture.depth.valid_fraction == pytest.approx(0.5)
    for row, col in [(0, 0), (1, 0), (1, 2)]:
        np.testing.assert_array_equal(picture.pixels[row, col], [0, 0, 0])
    np.testing.assert_array_equal(picture.pixels[0, 2], turbo(0.5))


def test_big_endian_32fc1_is_read_correctly() -> None:
    depth_m = np.array([[1.0, 4.0]], dtype=">f4")
    picture = raw_image(encoding="32FC1", width=2, height=1, step=8, data=depth_m.tobytes(), is_bigendian=True)
    assert picture.depth is not None
    assert (picture.depth.min_value, picture.depth.max_value) == (1.0, 4.0)


def test_mono16_is_a_depth_picture_in_raw_units() -> None:
    values = np.array([[100, 200]], dtype="<u2")
    picture = raw_image(encoding="mono16", width=2, height=1, step=4, data=values.tobytes(), is_bigendian=False)
    assert picture.depth is not None
    assert (picture.depth.unit, picture.depth.min_value, picture.depth.max_value) == ("raw", 100.0, 200.0)


def test_depth_without_valid_pixels_is_black_with_unknown_range() -> None:
    picture = raw_image(encoding="16UC1", width=2, height=2, step=4, data=bytes(8), is_bigendian=False)
    assert picture.depth is not None
    assert (picture.depth.min_value, picture.depth.max_value, picture.depth.valid_fraction) == (None, None, 0.0)
    assert not picture.pixels.any()


def bayer_mosaic(pattern: str, colour: tuple[int, int, int], *, width: int, height: int) -> npt.NDArray[np.uint8]:
    channel = {"r": 0, "g": 1, "b": 2}
    mosaic = np.zeros((height, width), dtype=np.uint8)
    for row in range(height):
        for col in range(width):
            mosaic[row, col] = colour[channel[pattern[(row % 2) * 2 + col % 2]]]
    return mosaic


@pytest.mark.parametrize("pattern", ["rggb", "bggr", "gbrg", "grbg"])
@pytest.mark.parametrize(("width", "height"), [(6, 4), (5, 3)])
def test_bayer_uniform_colour_comes_back_as_that_colour(pattern: str, width: int, height: int) -> None:
    mosaic = bayer_mosaic(pattern, (200, 120, 40), width=width, height=height)
    picture = raw_image(
        encoding=f"bayer_{pattern}8", width=width, height=height, step=width, data=mosaic, is_bigendian=False
    )
    assert picture.kind == "color"
    assert picture.pixels.shape == (height, width, 3)
    np.testing.assert_array_equal(picture.pixels, np.broadcast_to([200, 120, 40], (height, width, 3)))


def test_bayer_keeps_the_measured_value_at_each_site() -> None:
    mosaic = np.arange(16, dtype=np.uint8).reshape(4, 4) * 10
    picture = raw_image(encoding="bayer_rggb8", width=4, height=4, step=4, data=mosaic, is_bigendian=False)
    assert picture.pixels[0, 0, 0] == mosaic[0, 0]  # red site
    assert picture.pixels[0, 1, 1] == mosaic[0, 1]  # green site
    assert picture.pixels[1, 1, 2] == mosaic[1, 1]  # blue site
    # Red at the blue site (1, 1) is the mean of the four diagonal red sites.
    assert picture.pixels[1, 1, 0] == round((0 + 20 + 80 + 100) / 4)


@pytest.mark.parametrize("pattern", ["rggb", "bggr", "gbrg", "grbg"])
@pytest.mark.parametrize("big_endian", [False, True])
def test_sixteen_bit_bayer_shows_each_colour_scaled_to_eight_bits(pattern: str, big_endian: bool) -> None:
    colour = (51400, 25700, 65535)  # 200, 100 and 255 times 257
    sites = bayer_mosaic(pattern, (0, 1, 2), width=6, height=4)
    mosaic = np.array(colour, dtype=">u2" if big_endian else "<u2")[sites]
    step = 6 * 2 + 4  # padded rows
    padded = np.zeros((4, step), dtype=np.uint8)
    padded[:, :12] = mosaic.view(np.uint8).reshape(4, 12)
    picture = raw_image(
        encoding=f"bayer_{pattern}16", width=6, height=4, step=step, data=padded.tobytes(), is_bigendian=big_endian
    )
    assert (picture.kind, picture.width, picture.height) == ("color", 6, 4)
    np.testing.assert_array_equal(picture.pixels, np.broadcast_to([200, 100, 255], (4, 6, 3)))


def test_sixteen_bit_bayer_keeps_the_measured_value_at_each_site() -> None:
    mosaic = (np.arange(16, dtype=np.uint16).reshape(4, 4) * 10 * 257).astype("<u2")
    picture = raw_image(encoding="bayer_grbg16", width=4, height=4, step=8, data=mosaic.tobytes(), is_bigendian=False)
    assert picture.pixels[0, 0, 1] == 0  # green site
    assert picture.pixels[0, 1, 0] == 10  # red site
    assert picture.pixels[1, 0, 2] == 40  # blue site
    assert picture.pixels[1, 1, 1] == 50  # green site
    # Blue at the red site (0, 1) is the mean of the blue sites below it, (1, 0) and (1, 2).
    assert picture.pixels[0, 1, 2] == round((40 + 60) / 2)


# Standard BT.601 studio-swing (Y, U, V) values of colour bars and the RGB they stand for.
YUV_BARS = [((235, 128, 128), (255, 255, 255)), ((81, 90, 240), (255, 0, 0)), ((145, 54, 34), (0, 255, 0))]


@pytest.mark.parametrize(("encoding", "order"), [("yuv422", "UYVY"), ("yuv422_yuy2", "YUYV")])
def test_yuv422_byte_orders_give_bt601_colours(encoding: str, order: str) -> None:
    bars = [*YUV_BARS, ((41, 240, 110), (0, 0, 255))]
    row = bytearray()
    for (luma, u, v), _ in bars:
        values = {"Y": luma, "U": u, "V": v}
        row += bytes(values[name] for name in order)
    picture = raw_image(encoding=encoding, width=8, height=1, step=16, data=bytes(row), is_bigendian=False)
    expected = np.repeat(np.array([rgb for _, rgb in bars]), 2, axis=0)
    assert np.abs(picture.pixels[0].astype(int) - expected).max() <= 2


def test_yuv422_each_pixel_of_a_pair_keeps_its_own_luma() -> None:
    picture = raw_image(
        encoding="yuv422", width=2, height=1, step=4, data=bytes([128, 16, 128, 235]), is_bigendian=False
    )
    np.testing.assert_array_equal(picture.pixels[0], [[0, 0, 0], [255, 255, 255]])


def test_unknown_encoding_is_named_in_the_error() -> None:
    with pytest.raises(ValueError, match="'bgr16'"):
        raw_image(encoding="bgr16", width=1, height=1, step=6, data=bytes(6), is_bigendian=False)


def test_short_data_error_gives_the_expected_byte_count() -> None:
    with pytest.raises(ValueError, match=r"rgb8 image of 4x3 with step 12 needs 36 bytes"):
        raw_image(encoding="rgb8", width=4, height=3, step=12, data=bytes(20), is_bigendian=False)


def test_step_smaller_than_a_row_is_rejected() -> None:
    with pytest.raises(ValueError, match="step 8"):
        raw_image(encoding="rgb8", width=4, height=3, step=8, data=bytes(36), is_bigendian=False)


def test_yuv422_with_odd_width_is_rejected() -> None:
    with pytest.raises(ValueError, match="even width"):
        raw_image(encoding="yuv422", width=3, height=1, step=6, data=bytes(6), is_bigendian=False)


def test_picture_pixels_are_read_only() -> None:
    picture = raw_image(encoding="mono8", width=1, height=1, step=1, data=b"\x05", is_bigendian=False)
    with pytest.raises(ValueError, match="read-only"):
        picture.pixels[0, 0] = 1


def png_bytes(pixels: npt.NDArray[np.uint8] | npt.NDArray[np.uint16]) -> bytes:
    out = io.BytesIO()
    Image.fromarray(pixels).save(out, format="PNG")
    return out.getvalue()


def test_png_round_trip_gives_the_exact_pixels() -> None:
    picture = compressed_image(format="rgb8; png compressed bgr8", data=png_bytes(RGB))
    assert picture.kind == "color"
    assert (picture.width, picture.height) == (4, 3)
    np.testing.assert_array_equal(picture.pixels, RGB)


def test_grey_png_gives_a_mono_picture() -> None:
    grey = np.arange(12, dtype=np.uint8).reshape(3, 4)
    picture = compressed_image(format="mono8; png compressed", data=np.frombuffer(png_bytes(grey), dtype=np.uint8))
    assert picture.kind == "mono"
    np.testing.assert_array_equal(picture.pixels, grey)


def test_jpeg_keeps_colours_in_rgb_order() -> None:
    red = np.zeros((16, 16, 3), dtype=np.uint8)
    red[:, :, 0] = 220
    out = io.BytesIO()
    Image.fromarray(red).save(out, format="JPEG", quality=95)
    picture = compressed_image(format="bgr8; jpeg compressed bgr8", data=out.getvalue())
    assert picture.kind == "color"
    assert np.abs(picture.pixels.astype(int) - red).max() <= 3


def test_magic_bytes_win_over_the_format_string() -> None:
    picture = compressed_image(format="jpeg", data=png_bytes(RGB))
    np.testing.assert_array_equal(picture.pixels, RGB)


def test_compressed_depth_skips_the_12_byte_header() -> None:
    depth_mm = np.array([[0, 500], [1500, 2500]], dtype=np.uint16)
    data = struct.pack("<iff", 0, 0.0, 0.0) + png_bytes(depth_mm)
    picture = compressed_image(format="16UC1; compressedDepth png", data=data)
    assert picture.kind == "depth"
    assert picture.depth is not None
    assert (picture.depth.unit, picture.depth.min_value, picture.depth.max_value) == ("mm", 500.0, 2500.0)
    assert picture.depth.valid_fraction == pytest.approx(0.75)
    np.testing.assert_array_equal(picture.pixels[0, 0], [0, 0, 0])


def test_compressed_depth_without_header_still_decodes() -> None:
    depth_mm = np.array([[700, 900]], dtype=np.uint16)
    picture = compressed_image(format="16UC1; compressedDepth", data=png_bytes(depth_mm))
    assert picture.depth is not None
    assert (picture.depth.min_value, picture.depth.max_value) == (700.0, 900.0)


def test_compressed_depth_32fc1_is_dequantised_to_metres() -> None:
    # depth = A / (value - B) with A = 100, B = 0: values 50 and 25 are 2 m and 4 m, 0 is no measurement.
    inverse = np.array([[50, 25, 0]], dtype=np.uint16)
    data = struct.pack("<iff", 0, 100.0, 0.0) + png_bytes(inverse)
    picture = compressed_image(format="32FC1; compressedDepth png", data=data)
    assert picture.depth is not None
    assert (picture.depth.unit, picture.depth.min_value, picture.depth.max_value) == ("m", 2.0, 4.0)
    np.testing.assert_array_equal(picture.pixels[0, 2], [0, 0, 0])


@pytest.mark.parametrize("data", [b"", b"not an image at all", png_bytes(RGB)[:40]])
def test_corrupt_compressed_data_raises_a_clear_error(data: bytes) -> None:
    with pytest.raises(ValueError, match="the compressed image could not be decoded"):
        compressed_image(format="png", data=data)


def decode(encoded: Encoded) -> Image.Image:
    image = Image.open(io.BytesIO(encoded.data))
    image.load()
    return image


def colour_picture(width: int, height: int) -> Picture:
    rows, cols = np.indices((height, width))
    pixels = np.dstack([rows % 256, cols % 256, (rows + cols) % 256]).astype(np.uint8)
    data = pixels.tobytes()
    return raw_image(encoding="rgb8", width=width, height=height, step=width * 3, data=data, is_bigendian=False)


def test_large_colour_picture_is_scaled_to_max_size_as_jpeg() -> None:
    encoded = encode_picture(colour_picture(2000, 1000), max_size=1024)
    image = decode(encoded)
    assert encoded.mime_type == "image/jpeg"
    assert image.format == "JPEG"
    assert (encoded.width, encoded.height) == (1024, 512) == image.size


def test_scaling_keeps_the_aspect_ratio() -> None:
    encoded = encode_picture(colour_picture(900, 300), max_size=100)
    assert (encoded.width, encoded.height) == (100, 33)


def test_small_pictures_are_never_upscaled_and_sent_as_png() -> None:
    picture = colour_picture(100, 50)
    encoded = encode_picture(picture, max_size=1024)
    assert (encoded.mime_type, encoded.width, encoded.height) == ("image/png", 100, 50)
    np.testing.assert_array_equal(np.asarray(decode(encoded)), picture.pixels)


def test_mono_and_depth_pictures_are_sent_as_lossless_png() -> None:
    grey = (np.arange(400 * 300) % 251).astype(np.uint8)
    mono = raw_image(encoding="mono8", width=400, height=300, step=400, data=grey, is_bigendian=False)
    encoded = encode_picture(mono)
    assert encoded.mime_type == "image/png"
    np.testing.assert_array_equal(np.asarray(decode(encoded)), grey.reshape(300, 400))
    depth = raw_image(encoding="16UC1", width=400, height=300, step=800, data=bytes(240000), is_bigendian=False)
    assert encode_picture(depth).mime_type == "image/png"


def test_max_size_below_one_is_rejected() -> None:
    with pytest.raises(ValueError, match="max_size"):
        encode_picture(colour_picture(4, 4), max_size=0)
