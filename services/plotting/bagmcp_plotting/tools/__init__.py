"""The plotting service's MCP server: its declared plot tools and stored plots as resources."""

from __future__ import annotations

from mcp.server.mcpserver import MCPServer
from mcp.server.mcpserver.exceptions import ResourceNotFoundError

from bagmcp_kit.declared import ServiceTools
from bagmcp_kit.ingest_wait import IngestWait
from bagmcp_kit.longwork import LongWork
from bagmcp_kit.server import McpGuard, new_server
from bagmcp_plotting.artifacts import ARTIFACT_URI, Artifacts
from bagmcp_plotting.task_refs import RUN_JOB
from bagmcp_plotting.tools.plot_tools import (
    COMPARE_RUNS,
    PLOT_2D,
    PLOT_HISTOGRAM,
    PLOT_LIDAR_SCAN,
    PLOT_TIMESERIES,
    Plotting,
)
from bagmcp_shared.access import BagAccess
from bagmcp_shared.errors import ObjectNotFoundError

PURPOSE = (
    "Plots of robot bags as images you can see: time series, XY and trajectories, lidar scans, histograms, runs "
    "compared. A plot that becomes a job is stored when it succeeds: call the same tool again to see it."
)
PLOTTING = ServiceTools[Plotting](
    "plotting", RUN_JOB, (PLOT_TIMESERIES, PLOT_2D, PLOT_LIDAR_SCAN, PLOT_HISTOGRAM, COMPARE_RUNS)
)


def build_server(
    access: BagAccess, work: LongWork, artifacts: Artifacts, *, guard: McpGuard | None = None
) -> MCPServer:
    ingest = IngestWait(access.catalog, work.budget_s)
    tools = PLOTTING.specs(Plotting.of(access, artifacts), work)
    server = new_server("bagmcp-plotting", purpose=PURPOSE, tools=tools, guard=guard, ingest=ingest)
    _artifact_resource(server, artifacts)
    return server


def _artifact_resource(server: MCPServer, artifacts: Artifacts) -> None:
    """Stored plots as MCP resources (``bagmcp://artifacts/{id}``), for clients that read resources."""

    @server.resource(
        ARTIFACT_URI, name="plot", description="A stored plot (PNG) by its artifact id", mime_type="image/png"
    )
    def read_artifact(artifact: str) -> bytes:
        try:
            return artifacts.png(artifact)
        except ObjectNotFoundError as err:  # no such artifact: the message says what to do
            raise ResourceNotFoundError(str(err)) from err
