"""Building the analysis service from the resources of a way of running (team or embedded)."""

from __future__ import annotations

from mcp.server.mcpserver import MCPServer

from bagmcp_analysis.job_kinds import LIDAR, LOGS, STATISTICS, TF_TREE, TRAJECTORY, TRANSFORM, WINDOW
from bagmcp_analysis.queries.lidar import analyze_lidar
from bagmcp_analysis.queries.logs import analyze_logs
from bagmcp_analysis.queries.statistics import topic_statistics
from bagmcp_analysis.queries.tf import get_tf_tree, lookup_transform
from bagmcp_analysis.queries.trajectory import analyze_trajectory
from bagmcp_analysis.queries.window import summarize_window
from bagmcp_analysis.tools import build_server
from bagmcp_kit.longwork import LongWork
from bagmcp_kit.server import Guard
from bagmcp_shared.access import BagAccess
from bagmcp_shared.jobs import JobRegistry
from bagmcp_shared.resources import Resources


def build_registry(access: BagAccess) -> JobRegistry:
    """Every analysis as a job kind bound to the function doing it."""
    registry = JobRegistry()
    registry.add(TRAJECTORY, lambda p, progress: analyze_trajectory(access, p, progress))
    registry.add(LIDAR, lambda p, progress: analyze_lidar(access, p, progress))
    registry.add(LOGS, lambda p, progress: analyze_logs(access, p, progress))
    registry.add(TF_TREE, lambda p, progress: get_tf_tree(access, p, progress))
    registry.add(TRANSFORM, lambda p, progress: lookup_transform(access, p, progress))
    registry.add(STATISTICS, lambda p, progress: topic_statistics(access, p, progress))
    registry.add(WINDOW, lambda p, progress: summarize_window(access, p, progress))
    return registry


def build_analysis(res: Resources, *, guard: Guard | None = None) -> tuple[MCPServer, JobRegistry]:
    registry = build_registry(res.access)
    work = LongWork(res.jobs, res.runner, registry, budget_s=res.job_budget_s)
    return build_server(res.access, work, guard=guard), registry
