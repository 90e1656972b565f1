"""Tests for bagmcp_plotting.drawing.timeseries: time-series and overlay PNGs."""

from __future__ import annotations

import numpy as np
import pytest

from bagmcp_plotting.drawing.canvas import PALETTE
from bagmcp_plotting.drawing.lines import Line
from bagmcp_plotting.drawing.timeseries import Style, render_overlay, render_timeseries
from tests.fixtures.png_checks import MAX_PNG_BYTES, colour_mask, decode_png, distinct_colours

RNG = np.random.default_rng(7)
T_S = np.linspace(0.0, 300.0, 100_000)


def noisy(label: str, unit: str | None, scale: float) -> Line:
    return Line(label, unit, T_S, scale * (np.sin(T_S / 10.0) + RNG.normal(0.0, 0.2, T_S.size)))


@pytest.mark.parametrize("style", ["line", "step", "scatter"])
def test_100k_point_series_render_as_small_non_blank_1000x600_png(style: Style) -> None:
    png = render_timeseries([noisy("speed", "m/s", 1.0), noisy("cmd", "m/s", 1.2)], style=style, title="speed")
    pixels = decode_png(png)
    assert pixels.shape == (600, 1000, 3)
    assert len(png) < MAX_PNG_BYTES
    assert distinct_colours(pixels) >= 8
    assert colour_mask(pixels, PALETTE[0]).sum() > 1000
    assert colour_mask(pixels, PALETTE[1]).sum() > 1000


def line_rows(pixels: np.ndarray[tuple[int, ...], np.dtype[np.uint8]], hex_colour: str) -> float:
    """Mean pixel row of the rows where the colour runs across most of the plot (a horizontal line)."""
    counts = colour_mask(pixels, hex_colour, tolerance=20).sum(axis=1)
    rows = np.flatnonzero(counts > 400)
    assert rows.size > 0
    assert rows.max() - rows.min() <= 3
    return float(rows.mean())


def test_horizontal_line_is_drawn_at_its_value() -> None:
    t = np.linspace(0.0, 10.0, 100)
    lines = [
        Line("zero", "m", t, np.zeros(100)),
        Line("ten", "m", t, np.full(100, 10.0)),
        Line("two and a half", "m", t, np.full(100, 2.5)),
    ]
    pixels = decode_png(render_timeseries(lines, style="line", title="levels"))
    row_0, row_10, row_2_5 = (line_rows(pixels, PALETTE[i]) for i in range(3))
    assert row_10 < row_0  # larger values are higher up
    assert row_2_5 == pytest.approx(row_0 + 0.25 * (row_10 - row_0), abs=1.5)


def test_identical_input_gives_identical_bytes() -> None:
    lines = [noisy("speed", "m/s", 1.0), noisy("yaw rate", "rad/s", 0.5)]
    assert render_timeseries(lines, style="line", title="t") == render_timeseries(lines, style="line", title="t")


def test_twin_axes_colour_each_axis_like_its_line() -> None:
    png = render_timeseries([noisy("speed", "m/s", 1.0), noisy("yaw", "rad/s", 0.5)], style="line", title="twin")
    pixels = decode_png(png)
    assert pixels.shape == (600, 1000, 3)
    # The right-hand axis tick labels are orange: orange pixels right of the plot area.
    assert colour_mask(pixels[:, 930:], PALETTE[1]).sum() > 50


def test_stacked_panels_render_with_one_panel_per_group() -> None:
    lines = [noisy("speed", "m/s", 1.0), noisy("battery", "V", 48.0), noisy("current", "A", 5.0)]
    pixels = decode_png(render_timeseries(lines, style="line", title="stacked"))
    assert pixels.shape == (600, 1000, 3)
    green_rows = np.flatnonzero(colour_mask(pixels, PALETTE[2]).any(axis=1))
    blue_rows = np.flatnonzero(colour_mask(pixels, PALETTE[0]).sum(axis=1) > 100)
    assert blue_rows.max() < np.median(green_rows)  # first panel above the third


def test_many_dense_panels_stay_under_the_size_limit() -> None:
    rng = np.random.default_rng(3)
    lines = [Line(f"noise {i}", f"unit{i}", T_S, rng.normal(0.0, 1.0, T_S.size)) for i in range(8)]
    png = render_timeseries(lines, style="line", title="noise")
    assert len(png) < MAX_PNG_BYTES
    assert decode_png(png).shape == (1000, 1000, 3)


def test_more_than_eight_panels_are_refused() -> None:
    lines = [Line(f"s{i}", f"u{i}", T_S[:10], np.ones(10)) for i in range(9)]
    with pytest.raises(ValueError, match="at most 8"):
        render_timeseries(lines, style="line", title="too many")


def test_no_lines_is_refused() -> None:
    with pytest.raises(ValueError, match="at least one"):
        render_timeseries([], style="line", title="empty")


def test_all_nan_series_still_renders() -> None:
    png = render_timeseries([Line("gone", "m", T_S[:10], np.full(10, np.nan))], style="line", title="nan")
    assert decode_png(png).shape == (600, 1000, 3)


def test_overlay_gives_each_run_its_own_colour() -> None:
    runs = [Line(f"bag_{i}", "m/s", T_S, np.sin(T_S / 20.0 + i) + i) for i in range(6)]
    png = render_overlay(runs, title="speed per run", y_label="speed [m/s]", x_label="time [s]")
    pixels = decode_png(png)
    assert pixels.shape == (600, 1000, 3)
    assert len(png) < MAX_PNG_BYTES
    for colour in PALETTE[:6]:
        assert colour_mask(pixels, colour, tolerance=10).sum() > 300


def test_overlay_refuses_more_than_six_runs() -> None:
    runs = [Line(f"bag_{i}", None, T_S[:5], np.ones(5)) for i in range(7)]
    with pytest.raises(ValueError, match="At most 6"):
        render_overlay(runs, title="t", y_label="y", x_label="x")
