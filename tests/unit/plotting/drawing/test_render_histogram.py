"""Tests for bagmcp_plotting.drawing.histogram: legend statistics, bin choice and the PNG."""

from __future__ import annotations

import numpy as np
import pytest

from bagmcp_plotting.drawing.bins import freedman_diaconis_bins
from bagmcp_plotting.drawing.canvas import PALETTE
from bagmcp_plotting.drawing.histogram import histogram_legend, render_histogram
from tests.fixtures.png_checks import MAX_PNG_BYTES, colour_mask, decode_png, distinct_colours


def test_legend_gives_count_mean_and_percentiles_with_4_significant_digits() -> None:
    # 1..100: mean 50.5; linear percentiles p5 = 1 + 0.05*99, p50 = 50.5, p95 = 1 + 0.95*99.
    values = np.append(np.arange(1.0, 101.0), [np.nan, np.inf])
    assert histogram_legend(values, label="speed", unit="m/s") == (
        "speed [m/s]\nn = 100, mean = 50.50 m/s\np5 = 5.950, p50 = 50.50, p95 = 95.05 m/s"
    )


def test_legend_without_unit_has_no_unit_suffix() -> None:
    assert histogram_legend(np.array([2.0, 2.0]), label="count", unit=None) == (
        "count\nn = 2, mean = 2.000\np5 = 2.000, p50 = 2.000, p95 = 2.000"
    )


def test_freedman_diaconis_bins_follow_the_cube_root_rule() -> None:
    # Evenly spaced values on [0, 1]: IQR = 0.5, so span / (2 IQR / n^(1/3)) = n^(1/3).
    assert freedman_diaconis_bins(np.linspace(0.0, 1.0, 26_001)) == 30  # cube root 29.63
    assert freedman_diaconis_bins(np.linspace(0.0, 1.0, 101)) == 10  # 4.66 clipped up
    assert freedman_diaconis_bins(np.linspace(0.0, 1.0, 2_000_001)) == 100  # 126 clipped down


def test_constant_values_get_the_minimum_bin_count_and_still_render() -> None:
    values = np.full(500, 3.25)
    assert freedman_diaconis_bins(values) == 10
    pixels = decode_png(render_histogram(values, bins=None, label="voltage", unit="V", title="constant"))
    assert pixels.shape == (600, 1000, 3)
    assert colour_mask(pixels, PALETTE[0]).sum() > 1000


def test_100k_values_render_as_a_small_non_blank_png() -> None:
    values = np.random.default_rng(5).normal(1.0, 0.3, 100_000)
    png = render_histogram(values, bins=None, label="speed", unit="m/s", title="speed")
    pixels = decode_png(png)
    assert pixels.shape == (600, 1000, 3)
    assert len(png) < MAX_PNG_BYTES
    assert distinct_colours(pixels) >= 8
    assert png == render_histogram(values, bins=None, label="speed", unit="m/s", title="speed")


def test_only_nan_values_are_refused() -> None:
    with pytest.raises(ValueError, match="no finite values"):
        render_histogram(np.full(3, np.nan), bins=None, label="x", unit=None, title="t")


def test_bins_below_one_are_refused() -> None:
    with pytest.raises(ValueError, match="bins"):
        render_histogram(np.arange(5.0), bins=0, label="x", unit=None, title="t")
