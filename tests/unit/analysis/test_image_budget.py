"""Images are decoded only within the memory budget (checked on the header's size, before a pixel is
decoded), and the block-by-block conversions give exactly the pixels of a whole-image conversion."""

from __future__ import annotations

import io

import numpy as np
import pytest
from PIL import Image

from bagmcp_analysis import images
from bagmcp_analysis.images import compressed_image, raw_image
from bagmcp_shared import budget
from bagmcp_shared.settings import InputBudget


@pytest.fixture
def small_budget(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(budget, "_current", InputBudget(max_image_bytes=30_000))


def _png16(width: int, height: int) -> bytes:
    out = io.BytesIO()
    Image.fromarray(np.full((height, width), 1234, dtype=np.uint16)).save(out, format="PNG")
    return out.getvalue()


def test_a_compressed_depth_png_past_the_budget_is_refused_before_decoding(small_budget: None) -> None:
    header = b"\x00" * 12  # compressedDepth's quantisation header
    with pytest.raises(ValueError, match=r"100 x 101 pixels .* more than the 30,000 bytes .*BAGMCP_MAX_IMAGE_BYTES"):
        compressed_image(format="16UC1; compressedDepth png", data=header + _png16(100, 101))
    assert compressed_image(format="16UC1; compressedDepth png", data=header + _png16(90, 100)).width == 90


def test_a_raw_image_past_the_budget_is_refused(small_budget: None) -> None:
    data = bytes(200 * 100 * 2)
    with pytest.raises(ValueError, match="the 16UC1 image is 200 x 100 pixels"):
        raw_image(encoding="16UC1", width=200, height=100, step=400, data=data, is_bigendian=False)


@pytest.mark.parametrize("encoding", ["bayer_grbg8", "bayer_rggb16", "yuv422", "16UC1", "32FC1"])
def test_blocks_of_rows_give_the_pixels_of_the_whole_image(encoding: str, monkeypatch: pytest.MonkeyPatch) -> None:
    width, height = 12, 10
    native = {"bayer_grbg8": 1, "bayer_rggb16": 2, "yuv422": 2, "16UC1": 2, "32FC1": 4}[encoding]
    data = np.random.default_rng(7).integers(0, 255, width * height * native, dtype=np.uint8).tobytes()
    if encoding == "32FC1":
        data = np.linspace(0.5, 9.0, width * height, dtype=np.float32).tobytes()
    step = width * native

    def decoded() -> np.ndarray:
        return raw_image(encoding=encoding, width=width, height=height, step=step, data=data, is_bigendian=False).pixels

    whole = decoded()
    monkeypatch.setattr(images, "_BLOCK_PIXELS", 2 * width + 1)  # blocks of two rows, and an odd row phase
    assert np.array_equal(decoded(), whole)
    monkeypatch.setattr(images, "_BLOCK_PIXELS", 3 * width)
    assert np.array_equal(decoded(), whole)
