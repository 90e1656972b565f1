"""Trajectory plots (render_xy): y against x, optionally equal aspect, coloured by time, ends marked."""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
from matplotlib.figure import Figure

from bagmcp_plotting.drawing.canvas import LABEL_SIZE, LEGEND_SIZE, PALETTE, new_figure, style_axes, to_png
from bagmcp_plotting.drawing.decimate import extreme_indices
from bagmcp_plotting.drawing.fitting import add_legend

MAX_POINTS = 10_000
TIME_LABEL = "time from bag start [s]"
START_COLOR = "#2ca02c"
END_COLOR = "#d62728"


def render_xy(
    *,
    x: npt.NDArray[np.float64],
    y: npt.NDArray[np.float64],
    t_s: npt.NDArray[np.float64] | None = None,
    x_label: str,
    y_label: str,
    title: str,
    equal_aspect: bool,
    color_by_time: bool,
    mark_ends: bool,
) -> bytes:
    """PNG of a path; start = green circle, end = red square; colour by t_s with a colorbar when asked."""
    return to_png(
        draw_xy(
            x=x,
            y=y,
            t_s=t_s,
            x_label=x_label,
            y_label=y_label,
            title=title,
            equal_aspect=equal_aspect,
            color_by_time=color_by_time,
            mark_ends=mark_ends,
        )
    )


def draw_xy(
    *,
    x: npt.NDArray[np.float64],
    y: npt.NDArray[np.float64],
    t_s: npt.NDArray[np.float64] | None = None,
    x_label: str,
    y_label: str,
    title: str,
    equal_aspect: bool,
    color_by_time: bool,
    mark_ends: bool,
) -> Figure:
    """The figure of render_xy."""
    x = np.asarray(x, dtype=np.float64)
    y = np.asarray(y, dtype=np.float64)
    if x.shape != y.shape or x.ndim != 1:
        raise ValueError(f"x and y must be 1-D arrays of the same length, not shapes {x.shape} and {y.shape}.")
    if color_by_time and t_s is None:
        raise ValueError("Colouring by time needs the sample times t_s; pass them or set color_by_time to false.")
    t = np.zeros_like(x) if t_s is None else np.asarray(t_s, dtype=np.float64)
    if t.shape != x.shape:
        raise ValueError(f"t_s must have the same length as x and y ({x.size}), not {t.size}.")
    keep = np.isfinite(x) & np.isfinite(y) & (np.isfinite(t) | (not color_by_time))
    x, y, t = x[keep], y[keep], t[keep]
    figure = new_figure(title=title)
    axes = figure.add_subplot()
    shown = extreme_indices(x, y, max_points=MAX_POINTS)
    axes.plot(x[shown], y[shown], color=PALETTE[0], linewidth=1.5, label="trajectory", zorder=2)
    if color_by_time and x.size:
        dots = axes.scatter(x[shown], y[shown], c=t[shown], cmap="viridis", s=10, linewidths=0, zorder=3)
        bar = figure.colorbar(dots, ax=axes)
        bar.set_label(TIME_LABEL, fontsize=LABEL_SIZE)
    if mark_ends and x.size:
        axes.plot(x[:1], y[:1], "o", color=START_COLOR, markersize=11, markeredgecolor="black", label="start", zorder=4)
        axes.plot(x[-1:], y[-1:], "s", color=END_COLOR, markersize=10, markeredgecolor="black", label="end", zorder=4)
    if not x.size:
        axes.text(0.5, 0.5, "no finite points", transform=axes.transAxes, ha="center", fontsize=LABEL_SIZE)
    if equal_aspect:
        axes.set_aspect("equal", adjustable="datalim")
    style_axes(axes, x_label=x_label, y_label=y_label)
    handles, labels = axes.get_legend_handles_labels()
    add_legend(
        figure, list(zip(handles, labels, strict=True)), loc="outside lower center", columns=3, fontsize=LEGEND_SIZE
    )
    return figure
