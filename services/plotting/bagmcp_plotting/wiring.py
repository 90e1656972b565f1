"""Building the plotting service from the resources of a way of running (team or embedded)."""

from __future__ import annotations

from fastapi import APIRouter
from mcp.server.mcpserver import MCPServer

from bagmcp_kit.longwork import LongWork
from bagmcp_kit.runtime.resources import Resources
from bagmcp_kit.server import McpGuard
from bagmcp_plotting.artifacts import Artifacts, build_artifact_router
from bagmcp_plotting.tools import PLOTTING, build_server
from bagmcp_plotting.tools.plot_tools import Plotting
from bagmcp_shared.access import BagAccess
from bagmcp_shared.jobs import JobRegistry


def build_registry(access: BagAccess, artifacts: Artifacts) -> JobRegistry:
    """Every plot as a job kind bound to its plotter (derived from the declarations)."""
    return PLOTTING.registry(Plotting.of(access, artifacts))


def build_plotting(
    res: Resources,
    *,
    artifact_base_url: str = "",
    guard: McpGuard | None = None,
) -> tuple[MCPServer, APIRouter, JobRegistry]:
    artifacts = Artifacts(res.store, base_url=artifact_base_url)
    registry = build_registry(res.access, artifacts)
    work = LongWork(res.job_store, res.runner, registry, budget_s=res.job_budget_s)
    server = build_server(res.access, work, artifacts, guard=guard)
    return server, build_artifact_router(artifacts), registry
