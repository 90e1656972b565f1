"""The declarations of the plots: the PNG inline as image content, a link to the stored artifact, and a
summary of what was plotted (long reads become jobs on the plotting queue). Params models live beside the
plots in plots.py.

A plot already stored answers at once with its image, so after a job has succeeded the same call again
shows the picture; the answer that hands out the job says so."""

from __future__ import annotations

import base64
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, TypeVar

from mcp.server.mcpserver import Context
from mcp.types import CallToolResult, ContentBlock, ImageContent, ResourceLink, TextContent
from pydantic import BaseModel

from bagmcp_kit.declared import Declared
from bagmcp_kit.web.view_data import View, add_view
from bagmcp_plotting.artifacts import ARTIFACT_URI, Artifacts
from bagmcp_plotting.data import path_is_indexed
from bagmcp_plotting.plots import (
    COMPARE,
    HISTOGRAM,
    SCAN_PLOT,
    TIMESERIES,
    XY,
    CompareParams,
    HistogramParams,
    PlotDraw,
    Plotter,
    ScanPlotParams,
    TimeseriesParams,
    XYParams,
)
from bagmcp_plotting.reports import PlotReport
from bagmcp_plotting.views import PlotViews
from bagmcp_shared.access import BagAccess
from bagmcp_shared.topics import choose_pose_topic

P = TypeVar("P", bound=BaseModel)


@dataclass(frozen=True)
class Plotting:
    """What the plot tools work on: the bags, the stored plots, the plotter and the viewers' data."""

    access: BagAccess
    artifacts: Artifacts
    plotter: Plotter
    views: PlotViews

    @classmethod
    def of(cls, access: BagAccess, artifacts: Artifacts) -> Plotting:
        plotter = Plotter(access, artifacts)
        return cls(access, artifacts, plotter, PlotViews(access, plotter))

    def indexed(self, bag: str, paths: list[str]) -> bool:
        with self.access.open(bag) as ob:
            return all(path_is_indexed(ob, p) or ob.short(ob.topic_name(p.partition(".")[0])) for p in paths)

    def trajectory_small(self, params: XYParams) -> bool:
        with self.access.open(params.bag) as ob:
            topic, _, _ = choose_pose_topic(ob, params.topic)
            return ob.indexed(topic) or ob.short(topic)


def _summary(report: PlotReport) -> str:
    parts = ", ".join(f"{s.name} ({s.points} points, {s.min:.4g}..{s.max:.4g})" for s in report.series if s.points)
    return f"{report.title}: {parts or 'no finite points'}; image at {report.artifact.url}"


def _attach(plotting: Plotting, report: PlotReport) -> list[ContentBlock]:
    png = report.png or plotting.artifacts.png(report.artifact.id)  # a plot drawn inline has its bytes
    image = ImageContent(type="image", data=base64.b64encode(png).decode(), mime_type="image/png")
    uri = ARTIFACT_URI.format(
        artifact=report.artifact.id
    )  # readable with resources/read (the REST url is in the report)
    link = ResourceLink(type="resource_link", uri=uri, name=f"{report.artifact.id}.png", mime_type="image/png")
    return [image, link]


def _how_to_see(tool: str) -> str:
    return (
        f"When get_job says succeeded, call {tool} again with the same arguments: the plot is stored, so it "
        "answers at once with the image (get_job gives the report and the artifact's REST url)."
    )


Draw = Callable[[PlotViews], Callable[[Any, str], View]]


def _finish(tool: str, draw: Draw) -> Callable[[Context, Plotting, Any, CallToolResult], Any]:
    """The answer handing out a job says how to see the image later; a finished one carries the view."""

    async def finish(ctx: Context, plotting: Plotting, params: BaseModel, answer: CallToolResult) -> CallToolResult:
        if answer.structured_content is not None and "job" in answer.structured_content:
            answer.content.append(TextContent(type="text", text=_how_to_see(tool)))
        title = str(((answer.structured_content or {}).get("result") or {}).get("title", ""))
        return await add_view(ctx, answer, lambda: draw(plotting.views)(params, title))

    return finish


def _plot(
    tool: str,
    plot: str,
    description: str,
    params: type[P],
    work: Callable[[Plotter], PlotDraw[P]],
    draw: Draw,
    bags: Callable[[P], list[str]],
    quick: Callable[[Plotting, P], bool],
) -> Declared[Plotting, P, PlotReport]:
    """A plot tool: inline when the plot is stored or quick to make, else a job."""
    return Declared(
        tool,
        description,
        params,
        PlotReport,
        lambda plotting, p, progress: work(plotting.plotter)(p, progress, None),
        _summary,
        inline=lambda plotting, p: plotting.plotter.now(
            work(plotting.plotter), plot, p, bags(p), lambda q: quick(plotting, q)
        ),
        job=plot,
        view=_finish(tool, draw),
        attach=_attach,
    )


def _one_bag(params: TimeseriesParams | XYParams | ScanPlotParams | HistogramParams) -> list[str]:
    return [params.bag]


PLOT_TIMESERIES = _plot(
    "plot_timeseries",
    TIMESERIES,
    "Message paths over time (s from bag start); different scales get a second axis or panels. "
    'Example: paths=["/cmd_vel.linear.x", "/odom.twist.twist.linear.x"].',
    TimeseriesParams,
    lambda plotter: plotter.timeseries,
    lambda views: views.timeseries,
    _one_bag,
    lambda plotting, p: plotting.indexed(p.bag, p.paths),
)
PLOT_2D = _plot(
    "plot_2d",
    XY,
    "XY plot of two fields; without x and y, the trajectory of a pose topic in metres (GPS: east/north), "
    'equal aspect, start and end marked. Example: topic="/odom".',
    XYParams,
    lambda plotter: plotter.xy,
    lambda views: views.xy,
    _one_bag,
    lambda plotting, p: plotting.indexed(p.bag, [p.x, p.y]) if p.x and p.y else plotting.trajectory_small(p),
)
PLOT_LIDAR_SCAN = _plot(
    "plot_lidar_scan",
    SCAN_PLOT,
    "Polar plot of the scan nearest a time: robot at the centre, forward up, invalid ranges out. "
    "Example: time=12.5, within=0.5.",
    ScanPlotParams,
    lambda plotter: plotter.scan,
    lambda views: views.scan,
    _one_bag,
    lambda plotting, p: True,
)
PLOT_HISTOGRAM = _plot(
    "plot_histogram",
    HISTOGRAM,
    "Distribution of one message path, with count, mean and percentiles in the legend. "
    'Example: path="/cmd_vel.linear.x".',
    HistogramParams,
    lambda plotter: plotter.histogram,
    lambda views: views.histogram,
    _one_bag,
    lambda plotting, p: plotting.indexed(p.bag, [p.path]),
)
COMPARE_RUNS = _plot(
    "compare_runs",
    COMPARE,
    "The same message path from up to 6 bags overlaid, aligned on each bag's start or first motion. "
    'Example: bags=["run1", "run2"], path="/odom.twist.twist.linear.x".',
    CompareParams,
    lambda plotter: plotter.compare,
    lambda views: views.compare,
    lambda p: p.bags,
    lambda plotting, p: all(plotting.indexed(b, [p.path]) for b in p.bags),
)
