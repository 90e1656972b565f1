"""MCP adapters for the plots: the PNG inline as image content, a link to the stored artifact, and a
summary of what was plotted (long reads become jobs on the plotting queue).

A plot already stored answers at once with its image, so after a job has succeeded the same call again
shows the picture; the answer that hands out the job says so."""

from __future__ import annotations

import base64
from collections.abc import Callable
from typing import Annotated, Any, Literal, TypeVar

from mcp.server.mcpserver import Context
from mcp.types import CallToolResult, ContentBlock, ImageContent, ResourceLink, TextContent
from pydantic import BaseModel, Field

from bagmcp_kit.answers import tool_errors
from bagmcp_kit.arguments import READ_ONLY, BagRef, OptionalTopic, TimeArg, params_of
from bagmcp_kit.jobs import LongAnswer
from bagmcp_kit.longwork import LongWork
from bagmcp_kit.toolsets import BagTools, tool
from bagmcp_kit.web.view_data import View, add_view
from bagmcp_plotting.artifacts import ARTIFACT_URI, Artifacts
from bagmcp_plotting.data import path_is_indexed
from bagmcp_plotting.job_kinds import (
    COMPARE_RUNS,
    PLOT_2D,
    PLOT_HISTOGRAM,
    PLOT_SCAN,
    PLOT_TIMESERIES,
    CompareParams,
    HistogramParams,
    ScanPlotParams,
    TimeseriesParams,
    XYParams,
)
from bagmcp_plotting.plots import PlotDraw, Plotter
from bagmcp_plotting.reports import PlotReport
from bagmcp_plotting.views import PlotViews
from bagmcp_shared.access import BagAccess
from bagmcp_shared.jobs import JobKind
from bagmcp_shared.topics import choose_pose_topic

P = TypeVar("P", bound=BaseModel)
Path = Annotated[str, Field(description="e.g. /odom.twist.twist.linear.x")]
Answer = Annotated[CallToolResult, LongAnswer[PlotReport]]


def _summary(report: PlotReport) -> str:
    parts = ", ".join(f"{s.name} ({s.points} points, {s.min:.4g}..{s.max:.4g})" for s in report.series if s.points)
    return f"{report.title}: {parts or 'no finite points'}; image at {report.artifact.url}"


def _how_to_see(tool: str) -> str:
    return (
        f"When get_job says succeeded, call {tool} again with the same arguments: the plot is stored, so it "
        "answers at once with the image (get_job gives the report and the artifact's REST url)."
    )


class PlotTools(BagTools):
    def __init__(self, access: BagAccess, work: LongWork, artifacts: Artifacts) -> None:
        super().__init__(access, work)
        self._artifacts = artifacts
        self._plotter = plotter = Plotter(access, artifacts)
        self._draws: dict[str, PlotDraw[Any]] = {
            PLOT_TIMESERIES.name: plotter.timeseries,
            PLOT_2D.name: plotter.xy,
            PLOT_SCAN.name: plotter.scan,
            PLOT_HISTOGRAM.name: plotter.histogram,
            COMPARE_RUNS.name: plotter.compare,
        }
        views = PlotViews(access, plotter)
        self._views: dict[str, Callable[[Any, str], View]] = {
            PLOT_TIMESERIES.name: views.timeseries,
            PLOT_2D.name: views.xy,
            PLOT_SCAN.name: views.scan,
            PLOT_HISTOGRAM.name: views.histogram,
            COMPARE_RUNS.name: views.compare,
        }

    def _attach(self, report: PlotReport) -> list[ContentBlock]:
        png = report.png or self._artifacts.png(report.artifact.id)  # a plot drawn inline has its bytes
        image = ImageContent(type="image", data=base64.b64encode(png).decode(), mime_type="image/png")
        uri = ARTIFACT_URI.format(
            artifact=report.artifact.id
        )  # readable with resources/read (the REST url is in the report)
        link = ResourceLink(type="resource_link", uri=uri, name=f"{report.artifact.id}.png", mime_type="image/png")
        return [image, link]

    def _indexed(self, bag: str, paths: list[str]) -> bool:
        with self._access.open(bag) as ob:
            return all(path_is_indexed(ob, p) or ob.short(ob.topic_name(p.partition(".")[0])) for p in paths)

    async def _plot(
        self,
        ctx: Context,
        tool: str,
        kind: JobKind[P, PlotReport],
        params: P,
        bags: list[str],
        quick: Callable[[P], bool],
    ) -> CallToolResult:
        """Inline when the plot is stored or quick to make; otherwise a job, with how to see the image later."""
        answer = await self._work.run(
            ctx,
            kind,
            params,
            _summary,
            inline=lambda p: self._plotter.now(self._draws[kind.name], kind, p, bags, quick),
            attach=self._attach,
        )
        if answer.structured_content is not None and "job" in answer.structured_content:
            answer.content.append(TextContent(type="text", text=_how_to_see(tool)))
        return await add_view(ctx, answer, lambda: self._view(kind, params, answer))

    def _view(self, kind: JobKind[Any, PlotReport], params: BaseModel, answer: CallToolResult) -> View:
        """What the MCP Apps viewer and the web console draw for this plot (views.py)."""
        result = (answer.structured_content or {}).get("result") or {}
        return self._views[kind.name](params, str(result.get("title", "")))

    @tool(READ_ONLY, view=True)
    async def plot_timeseries(
        self,
        ctx: Context,
        bag: BagRef,
        paths: Annotated[list[str], Field(min_length=1, max_length=8, description="message paths (1-8)")],
        start: TimeArg | None = None,
        end: TimeArg | None = None,
        style: Literal["line", "step", "scatter"] = "line",
        title: Annotated[str | None, Field(description="default: the paths and window")] = None,
    ) -> Answer:
        """Message paths over time (s from bag start); different scales get a second axis or panels.
        Example: paths=["/cmd_vel.linear.x", "/odom.twist.twist.linear.x"]."""
        with tool_errors():
            params = params_of(TimeseriesParams, bag=bag, paths=paths, start=start, end=end, style=style, title=title)
        return await self._plot(
            ctx, "plot_timeseries", PLOT_TIMESERIES, params, [bag], lambda p: self._indexed(p.bag, p.paths)
        )

    @tool(READ_ONLY, view=True)
    async def plot_2d(
        self,
        ctx: Context,
        bag: BagRef,
        x: Annotated[str | None, Field(description="message path")] = None,
        y: Annotated[str | None, Field(description="path on x's topic")] = None,
        topic: OptionalTopic = None,
        start: TimeArg | None = None,
        end: TimeArg | None = None,
        color_by_time: bool = False,
    ) -> Answer:
        """XY plot of two fields; without x and y, the trajectory of a pose topic in metres (GPS: east/north),
        equal aspect, start and end marked. Example: topic="/odom"."""
        with tool_errors():
            params = params_of(
                XYParams, bag=bag, x=x, y=y, topic=topic, start=start, end=end, color_by_time=color_by_time
            )
        quick = (lambda p: self._indexed(p.bag, [p.x, p.y])) if x and y else self._trajectory_small
        return await self._plot(ctx, "plot_2d", PLOT_2D, params, [bag], quick)

    def _trajectory_small(self, params: XYParams) -> bool:
        with self._access.open(params.bag) as ob:
            topic, _, _ = choose_pose_topic(ob, params.topic)
            return ob.indexed(topic) or ob.short(topic)

    @tool(READ_ONLY, view=True)
    async def plot_lidar_scan(
        self,
        ctx: Context,
        bag: BagRef,
        time: TimeArg,
        topic: OptionalTopic = None,
        within: Annotated[float | None, Field(gt=0, description="m: draw this circle")] = None,
    ) -> Answer:
        """Polar plot of the scan nearest a time: robot at the centre, forward up, invalid ranges out.
        Example: time=12.5, within=0.5."""
        with tool_errors():
            params = params_of(ScanPlotParams, bag=bag, topic=topic, time=time, within_m=within)
        return await self._plot(ctx, "plot_lidar_scan", PLOT_SCAN, params, [bag], lambda p: True)

    @tool(READ_ONLY, view=True)
    async def plot_histogram(
        self,
        ctx: Context,
        bag: BagRef,
        path: Path,
        start: TimeArg | None = None,
        end: TimeArg | None = None,
        bins: Annotated[int | None, Field(ge=2, le=500, description="default: automatic")] = None,
    ) -> Answer:
        """Distribution of one message path, with count, mean and percentiles in the legend.
        Example: path="/cmd_vel.linear.x"."""
        with tool_errors():
            params = params_of(HistogramParams, bag=bag, path=path, start=start, end=end, bins=bins)
        return await self._plot(
            ctx, "plot_histogram", PLOT_HISTOGRAM, params, [bag], lambda p: self._indexed(p.bag, [p.path])
        )

    @tool(READ_ONLY, view=True)
    async def compare_runs(
        self,
        ctx: Context,
        bags: Annotated[list[str], Field(min_length=1, max_length=6, description="bag ids or names (1-6)")],
        path: Path,
        align: Literal["start", "motion"] = "start",
    ) -> Answer:
        """The same message path from up to 6 bags overlaid, aligned on each bag's start or first motion.
        Example: bags=["run1", "run2"], path="/odom.twist.twist.linear.x"."""
        with tool_errors():
            params = params_of(CompareParams, bags=bags, path=path, align=align)
        return await self._plot(
            ctx, "compare_runs", COMPARE_RUNS, params, bags, lambda p: all(self._indexed(b, [p.path]) for b in p.bags)
        )
