"""MCP adapters for motion and surroundings: analyze_trajectory, analyze_lidar_scan, summarize_window."""

from __future__ import annotations

from typing import Annotated, Any

from mcp.server.mcpserver import Context
from mcp.types import CallToolResult
from pydantic import Field

from bagmcp_analysis.job_kinds import LIDAR, TRAJECTORY, WINDOW, LidarParams, TrajectoryParams, WindowParams
from bagmcp_analysis.queries.lidar import lidar_is_small
from bagmcp_analysis.queries.trajectory import trajectory_is_small
from bagmcp_analysis.queries.window import window_is_small
from bagmcp_analysis.reports.lidar import LidarReport
from bagmcp_analysis.reports.trajectory import TrajectoryReport
from bagmcp_analysis.reports.window import WindowReport
from bagmcp_analysis.views import AnalysisViews
from bagmcp_kit.answers import tool_errors
from bagmcp_kit.arguments import READ_ONLY, BagRef, OptionalTopic, TimeArg, params_of
from bagmcp_kit.jobs import LongAnswer
from bagmcp_kit.longwork import LongWork
from bagmcp_kit.toolsets import BagTools, tool
from bagmcp_kit.web.view_data import add_view
from bagmcp_shared.access import BagAccess
from bagmcp_shared.wording import counted


def _trajectory_summary(r: TrajectoryReport) -> str:
    return (
        f"{r.topic}: {r.distance_2d_m:.2f} m in {r.duration_s:.2f} s, mean {r.mean_speed_mps or 0:.3f} m/s, "
        f"max {r.max_speed_mps or 0:.3f} m/s, {counted(len(r.stops), 'stop')}"
    )


def _lidar_summary(r: LidarReport) -> str:
    if r.mode == "scan":
        closest = f"closest {r.closest.range_m:.3f} m at {r.closest.bearing_deg:.1f} deg" if r.closest else "no return"
        return f"{r.topic} at {r.time.offset_s if r.time else 0:.3f} s: {closest}"
    first, seen = r.first_within, ""
    if first is not None:
        seen = f"; first within {r.within_m} m at {first.time.offset_s:.3f} s ({first.range_m:.3f} m)"
        seen += f", for {first.stays_s:.2f} s"
    elif r.within_m:
        seen = f"; nothing within {r.within_m} m"
    nearest = r.closest.range_m if r.closest else float("nan")
    return f"{counted(r.scans or 0, 'scan')} of {r.topic}; closest {nearest:.3f} m{seen}"


def _result(answer: CallToolResult) -> dict[str, Any]:
    return dict((answer.structured_content or {}).get("result") or {})


class MotionTools(BagTools):
    def __init__(self, access: BagAccess, work: LongWork) -> None:
        super().__init__(access, work)
        self._views = AnalysisViews(access)

    @tool(READ_ONLY, view=True)
    async def analyze_trajectory(
        self,
        ctx: Context,
        bag: BagRef,
        topic: OptionalTopic = None,
        start: TimeArg | None = None,
        end: TimeArg | None = None,
    ) -> Annotated[CallToolResult, LongAnswer[TrajectoryReport]]:
        """A path from odometry, pose, TF or GPS: distance, displacement, mean/max speed, moving/stopped time,
        stops, extents, start/end pose, waypoints. Example: start=20, end=75."""
        with tool_errors():
            params = params_of(TrajectoryParams, bag=bag, topic=topic, start=start, end=end)
        answer = await self._work.run(
            ctx, TRAJECTORY, params, _trajectory_summary, small=lambda p: trajectory_is_small(self._access, p)
        )
        return await add_view(ctx, answer, lambda: self._views.trajectory(params, _result(answer)))

    @tool(READ_ONLY, view=True)
    async def analyze_lidar_scan(
        self,
        ctx: Context,
        bag: BagRef,
        topic: OptionalTopic = None,
        time: Annotated[TimeArg | None, Field(description="one scan, nearest this time")] = None,
        start: TimeArg | None = None,
        end: TimeArg | None = None,
        within: Annotated[float | None, Field(gt=0, description="m: when something first came this close")] = None,
    ) -> Annotated[CallToolResult, LongAnswer[LidarReport]]:
        """LaserScan/PointCloud2. With `time`: one scan's valid ranges, closest obstacle and bearing, sectors,
        free gaps. Else over start..end: per-scan minimum and, with `within`, when something first came that
        close. Example: within=0.5."""
        with tool_errors():
            params = params_of(LidarParams, bag=bag, topic=topic, time=time, start=start, end=end, within_m=within)
        answer = await self._work.run(
            ctx, LIDAR, params, _lidar_summary, small=lambda p: lidar_is_small(self._access, p)
        )
        return await add_view(ctx, answer, lambda: self._views.lidar(params, _result(answer)))

    @tool(READ_ONLY)
    async def summarize_window(
        self, ctx: Context, bag: BagRef, start: TimeArg | None = None, end: TimeArg | None = None
    ) -> Annotated[CallToolResult, LongAnswer[WindowReport]]:
        """What happened in a window, as evidence with numbers: topics silent, slow or late against the whole
        bag, warnings and errors, motion and stops, closest obstacle. Example: start=45, end=55."""
        with tool_errors():
            params = params_of(WindowParams, bag=bag, start=start, end=end)
        return await self._work.run(
            ctx,
            WINDOW,
            params,
            lambda r: "; ".join(r.statements) or "nothing unusual",
            small=lambda p: window_is_small(self._access, p),
        )
