"""Building the plotting service from the resources of a way of running (team or embedded)."""

from __future__ import annotations

from fastapi import APIRouter
from mcp.server.mcpserver import MCPServer

from bagmcp_kit.longwork import LongWork
from bagmcp_kit.server import Guard
from bagmcp_plotting.artifacts import Artifacts, build_artifact_router
from bagmcp_plotting.job_kinds import COMPARE_RUNS, PLOT_2D, PLOT_HISTOGRAM, PLOT_SCAN, PLOT_TIMESERIES
from bagmcp_plotting.plots import Plotter
from bagmcp_plotting.tools import build_server
from bagmcp_shared.access import BagAccess
from bagmcp_shared.jobs import JobRegistry
from bagmcp_shared.resources import Resources


def build_registry(access: BagAccess, artifacts: Artifacts) -> JobRegistry:
    plotter = Plotter(access, artifacts)
    registry = JobRegistry()
    registry.add(PLOT_TIMESERIES, plotter.timeseries)
    registry.add(PLOT_2D, plotter.xy)
    registry.add(PLOT_SCAN, plotter.scan)
    registry.add(PLOT_HISTOGRAM, plotter.histogram)
    registry.add(COMPARE_RUNS, plotter.compare)
    return registry


def build_plotting(
    res: Resources,
    *,
    artifact_base_url: str = "",
    guard: Guard | None = None,
) -> tuple[MCPServer, APIRouter, JobRegistry]:
    artifacts = Artifacts(res.store, base_url=artifact_base_url)
    registry = build_registry(res.access, artifacts)
    work = LongWork(res.jobs, res.runner, registry, budget_s=res.job_budget_s)
    server = build_server(res.access, work, artifacts, guard=guard)
    return server, build_artifact_router(artifacts), registry
