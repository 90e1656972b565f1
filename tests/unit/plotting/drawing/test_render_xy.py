"""Tests for bagmcp_plotting.drawing.xy: trajectory PNGs with marked ends and time colouring."""

from __future__ import annotations

import numpy as np
import pytest

from bagmcp_plotting.drawing.canvas import PALETTE
from bagmcp_plotting.drawing.xy import END_COLOR, START_COLOR, render_xy
from tests.fixtures.png_checks import MAX_PNG_BYTES, centroid, colour_mask, decode_png, distinct_colours

VIRIDIS_END = "#fde725"


def straight(*, reverse: bool) -> bytes:
    x = np.linspace(0.0, 10.0, 500)
    if reverse:
        x = x[::-1]
    return render_xy(
        x=x,
        y=0.1 * np.sin(x),
        x_label="x [m]",
        y_label="y [m]",
        title="straight",
        equal_aspect=False,
        color_by_time=False,
        mark_ends=True,
    )


def test_start_is_a_green_mark_and_end_a_red_mark_at_the_right_ends() -> None:
    forward, backward = decode_png(straight(reverse=False)), decode_png(straight(reverse=True))
    # The legend is identical in both images, so pixels that differ are the end markers.
    start_fwd = colour_mask(forward, START_COLOR) & ~colour_mask(backward, START_COLOR)
    start_bwd = colour_mask(backward, START_COLOR) & ~colour_mask(forward, START_COLOR)
    end_fwd = colour_mask(forward, END_COLOR) & ~colour_mask(backward, END_COLOR)
    assert centroid(start_fwd)[1] + 500 < centroid(start_bwd)[1]  # x = 0 is far left of x = 10
    assert centroid(end_fwd)[1] == pytest.approx(centroid(start_bwd)[1], abs=3)


def test_colour_by_time_adds_viridis_colours_and_stays_small() -> None:
    t_s = np.linspace(0.0, 600.0, 100_000)
    png = render_xy(
        x=np.cos(t_s / 50.0) * t_s / 60.0,
        y=np.sin(t_s / 50.0) * t_s / 60.0,
        t_s=t_s,
        x_label="x [m]",
        y_label="y [m]",
        title="spiral",
        equal_aspect=True,
        color_by_time=True,
        mark_ends=True,
    )
    pixels = decode_png(png)
    assert pixels.shape == (600, 1000, 3)
    assert len(png) < MAX_PNG_BYTES
    assert distinct_colours(pixels) >= 8
    assert colour_mask(pixels, VIRIDIS_END, tolerance=20).sum() > 100


def circle_box_ratio(*, equal_aspect: bool) -> float:
    """Width / height in pixels of a drawn unit circle (rows above the legend at the bottom)."""
    angle = np.linspace(0.0, 2.0 * np.pi, 400)
    png = render_xy(
        x=np.cos(angle),
        y=np.sin(angle),
        x_label="x [m]",
        y_label="y [m]",
        title="circle",
        equal_aspect=equal_aspect,
        color_by_time=False,
        mark_ends=False,
    )
    path = colour_mask(decode_png(png)[:550], PALETTE[0])
    rows, cols = np.flatnonzero(path.any(axis=1)), np.flatnonzero(path.any(axis=0))
    return float(cols[-1] - cols[0]) / float(rows[-1] - rows[0])


def test_equal_aspect_draws_a_circle_as_round() -> None:
    assert circle_box_ratio(equal_aspect=True) == pytest.approx(1.0, abs=0.03)
    assert circle_box_ratio(equal_aspect=False) > 1.5


def test_identical_input_gives_identical_bytes() -> None:
    assert straight(reverse=False) == straight(reverse=False)


def test_colour_by_time_without_times_is_refused() -> None:
    with pytest.raises(ValueError, match="t_s"):
        render_xy(
            x=np.zeros(3),
            y=np.zeros(3),
            x_label="x",
            y_label="y",
            title="t",
            equal_aspect=True,
            color_by_time=True,
            mark_ends=False,
        )


def test_non_finite_points_are_skipped_and_ends_use_finite_points() -> None:
    x = np.array([np.nan, 0.0, 5.0, 10.0, np.inf])
    png = render_xy(
        x=x, y=np.zeros(5), x_label="x", y_label="y", title="t", equal_aspect=False, color_by_time=False, mark_ends=True
    )
    pixels = decode_png(png)
    assert colour_mask(pixels, START_COLOR).sum() > 50
    assert colour_mask(pixels, END_COLOR).sum() > 50
