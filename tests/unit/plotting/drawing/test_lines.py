"""Tests for bagmcp_plotting.drawing.lines: Line validation, summary_of and the drawn points."""

from __future__ import annotations

import numpy as np
import pytest

from bagmcp_plotting.drawing.lines import Line, magnitude_of, plot_points, scatter_points, summary_of


def test_summary_counts_finite_points_and_gives_plain_floats() -> None:
    line = Line("v", "m/s", np.arange(5.0), np.array([2.0, np.nan, -1.5, np.inf, 4.0]))
    count, low, high = summary_of(line)
    assert (count, low, high) == (3, -1.5, 4.0)
    assert type(count) is int
    assert type(low) is float
    assert type(high) is float


def test_summary_of_a_series_without_finite_points_is_unknown() -> None:
    assert summary_of(Line("v", None, np.arange(2.0), np.array([np.nan, np.nan]))) == (0, None, None)


def test_line_rejects_x_and_y_of_different_lengths() -> None:
    with pytest.raises(ValueError, match="'v'"):
        Line("v", None, np.arange(3.0), np.arange(4.0))


def test_drawn_points_of_a_long_series_keep_the_extremes() -> None:
    x = np.linspace(0.0, 10.0, 200_000)
    y = np.sin(x)
    y[777] = 9.0
    line = Line("v", None, x, y)
    for px, py in (plot_points(line), scatter_points(line)):
        assert py.max() == 9.0
        assert px.size < 10_000


def test_magnitude_is_the_largest_absolute_value_or_none_for_zero() -> None:
    assert magnitude_of(Line("a", None, np.arange(3.0), np.array([1.0, -7.0, 2.0]))) == 7.0
    assert magnitude_of(Line("b", None, np.arange(2.0), np.zeros(2))) is None


def test_a_line_breaks_where_the_series_has_a_gap() -> None:
    x = np.concatenate([np.arange(0.0, 20.0, 0.02), np.arange(22.0, 30.0, 0.02)])  # nothing from 20 to 22 s
    px, py = plot_points(Line("imu", None, x, np.ones(x.size)))
    breaks = np.flatnonzero(np.isnan(px))
    assert breaks.size == 1
    assert (px[breaks[0] - 1], px[breaks[0] + 1]) == pytest.approx((19.98, 22.0))
    assert np.isnan(py[breaks[0]])
    steady, _ = plot_points(Line("odom", None, np.arange(0.0, 30.0, 0.05), np.zeros(600)))
    assert not np.isnan(steady).any()
