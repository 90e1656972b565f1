"""Tests for the PointCloud2 summary on clouds packed with numpy (padding, row padding, big-endian)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from bagmcp_analysis.lidar.pointcloud import CloudField, cloud_stats

FLOAT32, FLOAT64, UINT16 = 7, 8, 4


def _closest(points: list[tuple[float, float, float]]) -> tuple[float, float, float]:
    finite = [p for p in points if all(math.isfinite(v) for v in p)]
    return min(finite, key=lambda p: math.sqrt(p[0] ** 2 + p[1] ** 2 + p[2] ** 2))


def test_padded_organised_cloud_is_read_through_offsets_and_row_padding() -> None:
    width, height, point_step, row_pad = 5, 3, 32, 24
    point = np.dtype(
        {
            "names": ["x", "y", "z", "ring", "intensity"],
            "formats": ["<f4", "<f4", "<f4", "<u2", "<f4"],
            "offsets": [0, 4, 8, 12, 16],
            "itemsize": point_step,
        }
    )
    rng = np.random.default_rng(7)
    coords = rng.uniform(-20, 20, size=(height, width, 3)).astype(np.float32)
    coords[1, 2] = (0.5, -0.5, 0.25)  # nearest point
    coords[0, 4, 1] = np.nan
    coords[2, 0, 2] = np.inf
    rows = []
    for r in range(height):
        row = np.zeros(width, dtype=point)
        row["x"], row["y"], row["z"] = coords[r, :, 0], coords[r, :, 1], coords[r, :, 2]
        rows.append(row.tobytes() + b"\xff" * row_pad)  # 0xff bytes read as NaN if the padding were decoded
    fields = [
        CloudField("x", 0, FLOAT32, 1),
        CloudField("y", 4, FLOAT32, 1),
        CloudField("z", 8, FLOAT32, 1),
        CloudField("ring", 12, UINT16, 1),
        CloudField("intensity", 16, FLOAT32, 1),
    ]
    stats = cloud_stats(
        fields=fields,
        data=b"".join(rows),
        point_step=point_step,
        row_step=width * point_step + row_pad,
        width=width,
        height=height,
        is_bigendian=False,
    )
    points = [(float(x), float(y), float(z)) for x, y, z in coords.reshape(-1, 3)]
    valid = [p for p in points if all(math.isfinite(v) for v in p)]
    assert (stats.points, stats.valid) == (15, 13)
    assert stats.fields == ["x", "y", "z", "ring", "intensity"]
    assert stats.extents is not None
    assert stats.extents.min_x_m == min(p[0] for p in valid)
    assert stats.extents.max_z_m == max(p[2] for p in valid)
    assert stats.closest is not None
    assert (stats.closest.x, stats.closest.y, stats.closest.z) == _closest(points) == (0.5, -0.5, 0.25)
    assert stats.closest.range_m == pytest.approx(math.sqrt(0.25 + 0.25 + 0.0625))
    assert stats.closest.bearing_deg == pytest.approx(-45.0)


def test_big_endian_float64_cloud_with_reordered_fields() -> None:
    point = np.dtype({"names": ["z", "x", "y"], "formats": [">f8"] * 3, "offsets": [0, 8, 16], "itemsize": 28})
    cloud = np.zeros(4, dtype=point)
    xyz = [(3.0, 4.0, 0.0), (-1.0, 0.0, 2.0), (0.0, -2.0, -2.0), (10.0, 10.0, 10.0)]
    for i, (x, y, z) in enumerate(xyz):
        cloud[i] = (z, x, y)
    fields = [CloudField("z", 0, FLOAT64, 1), CloudField("x", 8, FLOAT64, 1), CloudField("y", 16, FLOAT64, 1)]
    stats = cloud_stats(
        fields=fields, data=cloud.tobytes(), point_step=28, row_step=112, width=4, height=1, is_bigendian=True
    )
    nearest = _closest(xyz)
    assert stats.closest is not None
    assert (stats.closest.x, stats.closest.y, stats.closest.z) == nearest == (-1.0, 0.0, 2.0)
    assert stats.closest.range_m == pytest.approx(math.sqrt(5.0))
    assert stats.closest.bearing_deg == pytest.approx(180.0)
    assert stats.extents is not None
    extents = stats.extents
    box = (extents.min_x_m, extents.max_x_m, extents.min_y_m, extents.max_y_m, extents.min_z_m, extents.max_z_m)
    assert box == (-1.0, 10.0, -2.0, 10.0, -2.0, 10.0)


def test_cloud_without_z_is_rejected() -> None:
    fields = [CloudField("x", 0, FLOAT32, 1), CloudField("y", 4, FLOAT32, 1)]
    with pytest.raises(ValueError, match="no z field"):
        cloud_stats(fields=fields, data=b"\0" * 8, point_step=8, row_step=8, width=1, height=1, is_bigendian=False)


def test_truncated_data_is_rejected() -> None:
    fields = [CloudField(a, 4 * i, FLOAT32, 1) for i, a in enumerate("xyz")]
    with pytest.raises(ValueError, match="needs at least 24"):
        cloud_stats(fields=fields, data=b"\0" * 20, point_step=12, row_step=24, width=2, height=1, is_bigendian=False)


def test_empty_and_all_nan_clouds_have_no_extents() -> None:
    fields = [CloudField(a, 4 * i, FLOAT32, 1) for i, a in enumerate("xyz")]
    empty = cloud_stats(fields=fields, data=b"", point_step=12, row_step=0, width=0, height=1, is_bigendian=False)
    assert (empty.points, empty.valid, empty.extents, empty.closest) == (0, 0, None, None)
    nan_data = np.full(6, np.nan, dtype="<f4").tobytes()
    nan = cloud_stats(fields=fields, data=nan_data, point_step=12, row_step=24, width=2, height=1, is_bigendian=False)
    assert (nan.points, nan.valid, nan.extents, nan.closest) == (2, 0, None, None)
