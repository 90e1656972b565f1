"""Building the analysis service from the resources of a way of running (team or embedded)."""

from __future__ import annotations

from mcp.server.mcpserver import MCPServer

from bagmcp_analysis.tools import ANALYSIS, build_server
from bagmcp_kit.longwork import LongWork
from bagmcp_kit.runtime.resources import Resources
from bagmcp_kit.server import McpGuard
from bagmcp_shared.access import BagAccess
from bagmcp_shared.jobs import JobRegistry


def build_registry(access: BagAccess) -> JobRegistry:
    """Every long analysis as a job kind bound to its query on ``access`` (derived from the declarations)."""
    return ANALYSIS.registry(access)


def build_analysis(res: Resources, *, guard: McpGuard | None = None) -> tuple[MCPServer, JobRegistry]:
    registry = build_registry(res.access)
    work = LongWork(res.job_store, res.runner, registry, budget_s=res.job_budget_s)
    return build_server(res.access, work, guard=guard), registry
