"""The plotting service's MCP server: its tools, registered in one place."""

from __future__ import annotations

from mcp.server.mcpserver import MCPServer

from bagmcp_kit.arguments import READ_ONLY, ToolSpec, register
from bagmcp_kit.longwork import LongWork
from bagmcp_kit.server import new_server
from bagmcp_plotting.artifacts import Artifacts
from bagmcp_plotting.tools.plot_tools import PlotTools
from bagmcp_shared.access import BagAccess

PURPOSE = "Plots of robot bags as images you can see: time series, XY and trajectories, lidar scans, histograms."


def build_server(
    access: BagAccess,
    work: LongWork,
    artifacts: Artifacts,
    *,
    service_token: str | None = None,
    public_url: str = "http://127.0.0.1:8003",
) -> MCPServer:
    server = new_server("bagmcp-plotting", purpose=PURPOSE, service_token=service_token, public_url=public_url)
    plots = PlotTools(access, work, artifacts)
    register(
        server,
        [
            ToolSpec(plots.plot_timeseries, READ_ONLY),
            ToolSpec(plots.plot_2d, READ_ONLY),
            ToolSpec(plots.plot_lidar_scan, READ_ONLY),
            ToolSpec(plots.plot_histogram, READ_ONLY),
            ToolSpec(plots.compare_runs, READ_ONLY),
        ],
    )
    return server
