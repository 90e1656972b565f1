"""Tests for bagmcp_plotting.drawing.scan: polar laser scan PNGs oriented by REP 103."""

from __future__ import annotations

import numpy as np
import pytest

from bagmcp_plotting.drawing.canvas import PALETTE
from bagmcp_plotting.drawing.scan import CLOSEST_COLOR, INSIDE_COLOR, MAX_POINTS, render_scan, scan_points
from tests.fixtures.png_checks import MAX_PNG_BYTES, centroid, colour_mask, decode_png, distinct_colours


def cluster_pixels(direction_rad: float) -> np.ndarray[tuple[int, ...], np.dtype[np.uint8]]:
    """A scan whose only valid returns are an arc about 5 m away around one direction (closest at its middle)."""
    angles = np.linspace(-np.pi, np.pi, 720, endpoint=False)
    offset = np.angle(np.exp(1j * (angles - direction_rad)))
    ranges = np.where(np.abs(offset) < 0.2, 5.0 + 0.05 * np.abs(offset), np.inf)
    return decode_png(render_scan(angles_rad=angles, ranges_m=ranges, title="cluster", range_max_m=30.0))


def only_in_first(
    first: np.ndarray[tuple[int, ...], np.dtype[np.uint8]], second: np.ndarray[tuple[int, ...], np.dtype[np.uint8]]
) -> tuple[float, float]:
    """Centroid of point-coloured pixels present in `first` but not in `second` (legends are identical)."""
    return centroid(colour_mask(first, PALETTE[0]) & ~colour_mask(second, PALETTE[0]))


def test_forward_is_up() -> None:
    front, back = cluster_pixels(0.0), cluster_pixels(np.pi)
    front_row, front_col = only_in_first(front, back)
    back_row, back_col = only_in_first(back, front)
    assert front_row + 200 < back_row
    assert front_col == pytest.approx(back_col, abs=3)


def test_positive_angles_are_on_the_left() -> None:
    left, right = cluster_pixels(np.pi / 2), cluster_pixels(-np.pi / 2)
    left_row, left_col = only_in_first(left, right)
    right_row, right_col = only_in_first(right, left)
    assert left_col + 200 < right_col
    assert left_row == pytest.approx(right_row, abs=3)


def test_points_within_the_distance_are_red() -> None:
    angles = np.linspace(-2.0, 2.0, 1000)
    ranges = np.where(angles < 0.0, 1.0, 4.0)
    near = decode_png(render_scan(angles_rad=angles, ranges_m=ranges, title="near", range_max_m=10.0, within_m=2.0))
    plain = decode_png(render_scan(angles_rad=angles, ranges_m=ranges, title="near", range_max_m=10.0))
    assert colour_mask(near, INSIDE_COLOR).sum() > 200
    assert colour_mask(plain, INSIDE_COLOR).sum() == 0
    # The near points (negative angles, on the right) are red; the far ones on the left stay blue.
    _, red_col = centroid(colour_mask(near, INSIDE_COLOR) & ~colour_mask(plain, INSIDE_COLOR))
    assert red_col > centroid(colour_mask(near, PALETTE[0])[:, :700])[1]


def test_scan_png_is_small_deterministic_and_not_blank() -> None:
    angles = np.linspace(-2.35, 2.35, 1081)
    ranges = 3.0 + np.sin(3.0 * angles)
    ranges[::7] = np.nan
    png = render_scan(angles_rad=angles, ranges_m=ranges, title="scan", range_max_m=25.0, within_m=2.5)
    pixels = decode_png(png)
    assert pixels.shape == (600, 1000, 3)
    assert len(png) < MAX_PNG_BYTES
    assert distinct_colours(pixels) >= 8
    assert png == render_scan(angles_rad=angles, ranges_m=ranges, title="scan", range_max_m=25.0, within_m=2.5)


def test_ranges_beyond_range_max_are_not_drawn() -> None:
    angles = np.linspace(-1.0, 1.0, 200)
    beyond = render_scan(angles_rad=angles, ranges_m=np.full(200, 40.0), title="t", range_max_m=30.0)
    assert colour_mask(decode_png(beyond)[:, :700], PALETTE[0]).sum() == 0


def test_invalid_range_max_is_refused() -> None:
    with pytest.raises(ValueError, match="range_max_m"):
        render_scan(angles_rad=np.zeros(1), ranges_m=np.ones(1), title="t", range_max_m=0.0)


def test_the_one_close_return_of_a_dense_scan_is_drawn_counted_and_marked() -> None:
    angles = np.linspace(-np.pi, np.pi, 60_000, endpoint=False)
    ranges = np.full(angles.size, 8.0)
    ranges[30_001] = 1.0  # one return, at an index a stride of 3 would skip
    ranges[30_004] = 1.5  # inside the circle too, thinned away for drawing but counted
    points = scan_points(angles, ranges, range_max_m=30.0, within_m=2.0)
    assert points.range_m.size <= MAX_POINTS + 3
    assert 1.0 in points.range_m
    assert points.inside_count == 2
    assert points.closest == pytest.approx((1.0, np.degrees(angles[30_001])))
    png = render_scan(angles_rad=angles, ranges_m=ranges, title="dense", range_max_m=30.0, within_m=2.0)
    assert colour_mask(decode_png(png), CLOSEST_COLOR).sum() > 50  # the diamond and its legend marker
