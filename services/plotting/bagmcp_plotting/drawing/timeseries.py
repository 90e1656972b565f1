"""Time-series plots: render_timeseries (single axis, twin y axes or stacked panels) and render_overlay.

Long series are min/max decimated before drawing; every line gets a tab10 colour by its position and
one legend names every line.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Literal

from matplotlib.artist import Artist
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from bagmcp_plotting.drawing.canvas import HEIGHT_IN, LEGEND_SIZE, PALETTE, axis_label, new_figure, style_axes, to_png
from bagmcp_plotting.drawing.fitting import add_legend
from bagmcp_plotting.drawing.layout import Layout, group_indices, layout_for
from bagmcp_plotting.drawing.lines import Line, plot_points, scatter_points

Style = Literal["line", "step", "scatter"]
MAX_OVERLAY_RUNS = 6
MAX_PANELS = 8
MAX_HEIGHT_IN = 10.0
DEFAULT_X_LABEL = "time from bag start [s]"


def render_timeseries(lines: Sequence[Line], *, style: Style, title: str, x_label: str = DEFAULT_X_LABEL) -> bytes:
    """PNG of the lines against time; axes chosen by layout_for (same unit shares an axis)."""
    return to_png(draw_timeseries(lines, style=style, title=title, x_label=x_label))


def draw_timeseries(lines: Sequence[Line], *, style: Style, title: str, x_label: str = DEFAULT_X_LABEL) -> Figure:
    """The figure of render_timeseries."""
    if not lines:
        raise ValueError("There is no series to plot; pass at least one line.")
    if style not in ("line", "step", "scatter"):
        raise ValueError(f"The plot style {style!r} is unknown; use 'line', 'step' or 'scatter'.")
    groups = group_indices(lines)
    if len(groups) > MAX_PANELS:
        raise ValueError(
            f"These series need {len(groups)} separate panels (different units or scales), but at most "
            f"{MAX_PANELS} fit in one plot; plot fewer series at a time."
        )
    layout = layout_for(lines)
    height_in = _stacked_height_in(len(groups)) if layout == "stacked" else HEIGHT_IN
    figure = new_figure(title=title, height_in=height_in)
    axes_list = _make_axes(figure, layout=layout, panels=len(groups))
    handles: dict[int, tuple[Artist, str]] = {}
    for panel, (axes, group) in enumerate(zip(axes_list, groups, strict=True)):
        side = (" (left axis)", " (right axis)")[panel] if layout == "twin" else ""
        for index in group:
            handles[index] = (_draw(axes, lines[index], style=style, color=_color(index)), lines[index].label + side)
        is_bottom = layout != "stacked" or panel == len(groups) - 1
        style_axes(
            axes,
            x_label=x_label if is_bottom else None,
            y_label=_group_label(lines, group),
            grid=panel == 0 or layout == "stacked",
        )
        if layout == "twin" and len(group) == 1:
            _match_axis_colour(axes, _color(group[0]))
    _legend(figure, [handles[index] for index in sorted(handles)])
    return figure


def render_overlay(lines: Sequence[Line], *, title: str, y_label: str, x_label: str) -> bytes:
    """PNG of up to 6 runs of one quantity on one axis, one tab10 colour per run, legend with the labels."""
    return to_png(draw_overlay(lines, title=title, y_label=y_label, x_label=x_label))


def draw_overlay(lines: Sequence[Line], *, title: str, y_label: str, x_label: str) -> Figure:
    """The figure of render_overlay."""
    if not lines:
        raise ValueError("There is no run to overlay; pass at least one line.")
    if len(lines) > MAX_OVERLAY_RUNS:
        raise ValueError(f"At most {MAX_OVERLAY_RUNS} runs can be overlaid, not {len(lines)}; pick fewer bags.")
    figure = new_figure(title=title)
    axes = figure.add_subplot()
    handles = [(_draw(axes, line, style="line", color=_color(i)), line.label) for i, line in enumerate(lines)]
    style_axes(axes, x_label=x_label, y_label=y_label)
    _legend(figure, handles)
    return figure


def _color(index: int) -> str:
    return PALETTE[index % len(PALETTE)]


def _draw(axes: Axes, line: Line, *, style: Style, color: str) -> Artist:
    if style == "scatter":
        x, y = scatter_points(line)
        return axes.scatter(x, y, s=5, marker="s", color=color, label=line.label, linewidths=0)
    x, y = plot_points(line)
    if style == "step":
        return axes.step(x, y, where="post", color=color, linewidth=1.5, label=line.label)[0]
    return axes.plot(x, y, color=color, linewidth=1.5, label=line.label)[0]


def _group_label(lines: Sequence[Line], group: list[int]) -> str:
    """The names of the group's lines, or what they share (``linear.x``) when that would be too long."""
    labels = [lines[index].label for index in group]
    names = ", ".join(labels)
    if len(names) > 40:
        names = _shared_field(labels) or "value"
    return axis_label(names, lines[group[0]].unit)


def _shared_field(labels: list[str]) -> str:
    """The trailing path steps every label ends with, e.g. ``linear.x``; "" when they share none."""
    split = [label.split(".") for label in labels]
    shared: list[str] = []
    for steps in zip(*(reversed(s) for s in split), strict=False):
        if len(set(steps)) > 1 or any("/" in step for step in steps):
            break
        shared.insert(0, steps[0])
    return ".".join(shared)


def _match_axis_colour(axes: Axes, color: str) -> None:
    axes.yaxis.label.set_color(color)
    axes.tick_params(axis="y", colors=color)


def _make_axes(figure: Figure, *, layout: Layout, panels: int) -> list[Axes]:
    if layout == "stacked":
        return list(figure.subplots(panels, 1, sharex=True, squeeze=False)[:, 0])
    axes = figure.add_subplot()
    return [axes, axes.twinx()] if layout == "twin" else [axes]


def _legend(figure: Figure, entries: list[tuple[Artist, str]]) -> None:
    """One legend below the plot naming every line, in the order the lines were given, inside the figure."""
    columns = min(len(entries), 4 if len(entries) <= 8 else 6)
    add_legend(figure, entries, loc="outside lower center", columns=columns, fontsize=LEGEND_SIZE)


def _stacked_height_in(panels: int) -> float:
    """6 in for up to 4 panels, then 1.5 in per panel up to MAX_HEIGHT_IN (keeps the PNG under 200 KB)."""
    return min(MAX_HEIGHT_IN, max(HEIGHT_IN, 1.5 * panels))
