"""The analysis service's MCP server: its declared tools, in the order they are listed."""

from __future__ import annotations

from mcp.server.mcpserver import MCPServer

from bagmcp_analysis.task_refs import RUN_JOB
from bagmcp_analysis.tools.image_tools import IMAGE
from bagmcp_analysis.tools.motion_tools import LIDAR, TRAJECTORY, WINDOW
from bagmcp_analysis.tools.record_tools import LOGS, STATISTICS, TF_TREE, TRANSFORM
from bagmcp_kit.declared import ServiceTools
from bagmcp_kit.ingest_wait import IngestWait
from bagmcp_kit.longwork import LongWork
from bagmcp_kit.server import McpGuard, new_server
from bagmcp_shared.access import BagAccess

PURPOSE = "Robot bag analysis: trajectories, lidar obstacles, logs, TF frames, images, topic timing, windows."
ANALYSIS = ServiceTools[BagAccess](
    "analysis", RUN_JOB, (TRAJECTORY, LIDAR, WINDOW, LOGS, TF_TREE, TRANSFORM, STATISTICS, IMAGE)
)


def build_server(access: BagAccess, work: LongWork, *, guard: McpGuard | None = None) -> MCPServer:
    tools = ANALYSIS.specs(access, work)
    ingest = IngestWait(access.catalog, work.budget_s)
    return new_server("bagmcp-analysis", purpose=PURPOSE, tools=tools, guard=guard, ingest=ingest)
