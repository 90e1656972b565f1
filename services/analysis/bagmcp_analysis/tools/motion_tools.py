"""The declarations of the motion and surroundings tools: analyze_trajectory, analyze_lidar_scan,
summarize_window (their params models live beside their queries)."""

from __future__ import annotations

from typing import Any

from mcp.server.mcpserver import Context
from mcp.types import CallToolResult

from bagmcp_analysis.queries.lidar import LidarParams, analyze_lidar, lidar_is_small
from bagmcp_analysis.queries.trajectory import TrajectoryParams, analyze_trajectory, trajectory_is_small
from bagmcp_analysis.queries.window import WindowParams, summarize_window, window_is_small
from bagmcp_analysis.reports.lidar import LidarReport
from bagmcp_analysis.reports.trajectory import TrajectoryReport
from bagmcp_analysis.reports.window import WindowReport
from bagmcp_analysis.views import AnalysisViews
from bagmcp_kit.declared import Declared
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


async def _trajectory_view(
    ctx: Context, access: BagAccess, params: TrajectoryParams, answer: CallToolResult
) -> CallToolResult:
    return await add_view(ctx, answer, lambda: AnalysisViews(access).trajectory(params, _result(answer)))


async def _lidar_view(ctx: Context, access: BagAccess, params: LidarParams, answer: CallToolResult) -> CallToolResult:
    return await add_view(ctx, answer, lambda: AnalysisViews(access).lidar(params, _result(answer)))


TRAJECTORY = Declared(
    "analyze_trajectory",
    "A path from odometry, pose, TF or GPS: distance, displacement, mean/max speed, moving/stopped time, "
    "stops, extents, start/end pose, waypoints. Example: start=20, end=75.",
    TrajectoryParams,
    TrajectoryReport,
    analyze_trajectory,
    _trajectory_summary,
    small=trajectory_is_small,
    job="trajectory",
    view=_trajectory_view,
)
LIDAR = Declared(
    "analyze_lidar_scan",
    "LaserScan/PointCloud2. With `time`: one scan's valid ranges, closest obstacle and bearing, sectors, "
    "free gaps. Else over start..end: per-scan minimum and, with `within`, when something first came that "
    "close. Example: within=0.5.",
    LidarParams,
    LidarReport,
    analyze_lidar,
    _lidar_summary,
    small=lidar_is_small,
    job="lidar",
    view=_lidar_view,
)
WINDOW = Declared(
    "summarize_window",
    "What happened in a window, as evidence with numbers: topics silent, slow or late against the whole "
    "bag, warnings and errors, motion and stops, closest obstacle. Example: start=45, end=55.",
    WindowParams,
    WindowReport,
    summarize_window,
    lambda r: "; ".join(r.statements) or "nothing unusual",
    small=window_is_small,
)
