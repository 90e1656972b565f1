"""Histograms (render_histogram) with a legend giving count, mean and p5/p50/p95.

Bins (bins.py) default to the Freedman–Diaconis rule; non-finite values are dropped.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from bagmcp_plotting.drawing.bins import finite_values, freedman_diaconis_bins
from bagmcp_plotting.drawing.canvas import LEGEND_SIZE, PALETTE, axis_label, new_figure, style_axes, to_png


def render_histogram(
    values: npt.NDArray[np.float64], *, bins: int | None, label: str, unit: str | None, title: str
) -> bytes:
    """PNG histogram of the finite values; a constant series draws a single bar."""
    finite = finite_values(values)
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
    finite = finite_values(values)
    p5, p50, p95 = (float(p) for p in np.percentile(finite, [5, 50, 95]))
    suffix = f" {unit}" if unit else ""
    return (
        f"{axis_label(label, unit)}\n"
        f"n = {finite.size}, mean = {float(finite.mean()):#.4g}{suffix}\n"
        f"p5 = {p5:#.4g}, p50 = {p50:#.4g}, p95 = {p95:#.4g}{suffix}"
    )
