"""Tests for bagmcp_plotting.drawing.decimate: minmax_decimate (series) and extreme_indices (paths, scans)."""

from __future__ import annotations

import numpy as np
import pytest

from bagmcp_plotting.drawing.decimate import extreme_indices, minmax_decimate


def test_a_single_spike_in_a_million_points_survives() -> None:
    x = np.linspace(0.0, 1000.0, 1_000_000)
    y = np.sin(x)
    y[123_456] = 50.0
    y[765_432] = -30.0
    dx, dy = minmax_decimate(x, y, columns=1500)
    assert dx.size <= 3000
    assert dy.max() == 50.0
    assert dy.min() == -30.0
    assert x[123_456] in dx
    assert x[765_432] in dx


def test_output_keeps_x_order_and_each_column_min_and_max() -> None:
    # 10 points over [0, 9] in 2 columns: [0, 4.5) holds x = 0..4, [4.5, 9] holds x = 5..9.
    x = np.arange(10.0)
    y = np.array([3.0, 1.0, 4.0, 1.0, 5.0, 9.0, 2.0, 6.0, 5.0, 3.0])
    dx, dy = minmax_decimate(x, y, columns=2)
    np.testing.assert_array_equal(dx, [1.0, 4.0, 5.0, 6.0])
    np.testing.assert_array_equal(dy, [1.0, 5.0, 9.0, 2.0])


def test_short_series_are_returned_unchanged() -> None:
    x = np.arange(3000.0)
    y = np.cos(x)
    dx, dy = minmax_decimate(x, y, columns=1500)
    np.testing.assert_array_equal(dx, x)
    np.testing.assert_array_equal(dy, y)


def test_nan_values_are_dropped_from_long_series() -> None:
    x = np.arange(10_000.0)
    y = np.ones(10_000)
    y[::3] = np.nan
    _, dy = minmax_decimate(x, y, columns=100)
    assert np.isfinite(dy).all()
    assert dy.size <= 200


def test_unsorted_x_is_decimated_in_x_order() -> None:
    rng = np.random.default_rng(1)
    x = rng.permutation(5000).astype(np.float64)
    y = x**2
    dx, dy = minmax_decimate(x, y, columns=50)
    assert (np.diff(dx) > 0).all()
    np.testing.assert_array_equal(dy, dx**2)
    assert (dx[0], dx[-1]) == (0.0, 4999.0)


def test_identical_x_values_keep_only_the_extremes() -> None:
    x = np.zeros(100)
    y = np.arange(100.0)
    dx, dy = minmax_decimate(x, y, columns=10)
    np.testing.assert_array_equal(dy, [0.0, 99.0])
    np.testing.assert_array_equal(dx, [0.0, 0.0])


def test_columns_below_one_are_rejected() -> None:
    with pytest.raises(ValueError, match="columns"):
        minmax_decimate(np.arange(5.0), np.arange(5.0), columns=0)


def test_mismatched_lengths_are_rejected() -> None:
    with pytest.raises(ValueError, match="same length"):
        minmax_decimate(np.arange(5.0), np.arange(4.0))


def test_a_thinned_path_keeps_its_whole_extent_and_both_ends() -> None:
    t = np.linspace(0.0, 100.0, 200_001)
    x, y = np.cos(t), np.sin(t)
    x[54_321], y[150_003] = 40.0, -25.0  # single far points that a stride would skip
    kept = extreme_indices(x, y, max_points=10_000)
    assert kept.size <= 10_000 + 10
    assert np.all(np.diff(kept) > 0)  # still in path order
    assert (kept[0], kept[-1]) == (0, t.size - 1)
    assert (x[kept].min(), x[kept].max(), y[kept].min(), y[kept].max()) == (x.min(), 40.0, -25.0, y.max())


def test_a_thinned_scan_keeps_its_closest_and_farthest_returns() -> None:
    ranges = np.full(60_001, 8.0)
    ranges[31_337], ranges[7] = 0.42, 29.0
    kept = extreme_indices(ranges, max_points=20_000)
    assert kept.size <= 20_000 + 3
    assert 31_337 in kept
    assert 7 in kept


def test_few_points_are_all_kept() -> None:
    np.testing.assert_array_equal(extreme_indices(np.arange(5.0), max_points=5), np.arange(5))
    with pytest.raises(ValueError, match="one value per point"):
        extreme_indices(np.arange(5.0), np.arange(4.0), max_points=2)
