"""Histograms (render_histogram) with a legend giving count, mean and p5/p50/p95.

Bins default to the Freedman–Diaconis rule clipped to [MIN_BINS, MAX_BINS]; non-finite values are dropped.
"""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

from bagmcp_plotting.drawing.canvas import LEGEND_SIZE, PALETTE, axis_label, new_figure, style_axes, to_png

MIN_BINS = 10
MAX_BINS = 100


def render_histogram(
    values: npt.NDArray[np.float64], *, bins: int | None, label: str, unit: str | None, title: str
) -> bytes:
    """PNG histogram of the finite values; a constant series draws a single bar."""
    finite = _finite(values)
    if bins is not None and bins < 1:
        raise ValueError(f"bins must be at least 1, not {bins}; leave it empty for an automatic choice.")
    figure = new_figure(title=title)
    axes = figure.add_subplot()
    axes.hist(
        finite,
        bins=bins or freedman_diaconis_bins(finite),
        color=PALETTE[0],
        edgecolor="white",
        linewidth=0.5,
        label=histogram_legend(finite, label=label, unit=unit),
    )
    style_axes(axes, x_label=axis_label(label, unit), y_label="count")
    axes.legend(loc="best", fontsize=LEGEND_SIZE)
    return to_png(figure)


def histogram_legend(values: npt.NDArray[np.float64], *, label: str, unit: str | None) -> str:
    """Legend text: label [unit], count, mean and p5/p50/p95 with 4 significant digits."""
    finite = _finite(values)
    p5, p50, p95 = (float(p) for p in np.percentile(finite, [5, 50, 95]))
    suffix = f" {unit}" if unit else ""
    return (
        f"{axis_label(label, unit)}\n"
        f"n = {finite.size}, mean = {float(finite.mean()):#.4g}{suffix}\n"
        f"p5 = {p5:#.4g}, p50 = {p50:#.4g}, p95 = {p95:#.4g}{suffix}"
    )


def freedman_diaconis_bins(values: npt.NDArray[np.float64]) -> int:
    """Bin count from the Freedman–Diaconis width 2·IQR/n^(1/3), clipped to [MIN_BINS, MAX_BINS]."""
    finite = _finite(values)
    q25, q75 = np.percentile(finite, [25, 75])
    iqr = float(q75 - q25)
    span = float(finite.max() - finite.min())
    if iqr <= 0 or span <= 0:
        return MIN_BINS
    width = 2.0 * iqr / float(np.cbrt(finite.size))
    return min(MAX_BINS, max(MIN_BINS, math.ceil(span / width)))


def _finite(values: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    array = np.asarray(values, dtype=np.float64).reshape(-1)
    finite = array[np.isfinite(array)]
    if finite.size == 0:
        raise ValueError("There are no finite values to draw a histogram of; pick a field or time range with data.")
    return finite
