"""The analysis service's MCP server: its tool classes, in the order their tools are listed."""

from __future__ import annotations

from mcp.server.mcpserver import MCPServer

from bagmcp_analysis.tools.image_tools import ImageTools
from bagmcp_analysis.tools.motion_tools import MotionTools
from bagmcp_analysis.tools.record_tools import RecordTools
from bagmcp_kit.ingest_wait import IngestWait
from bagmcp_kit.longwork import LongWork
from bagmcp_kit.server import Guard, new_server
from bagmcp_shared.access import BagAccess

PURPOSE = "Robot bag analysis: trajectories, lidar obstacles, logs, TF frames, images, topic timing, windows."


def build_server(access: BagAccess, work: LongWork, *, guard: Guard | None = None) -> MCPServer:
    tools = [MotionTools(access, work), RecordTools(access, work), ImageTools(access)]
    ingest = IngestWait(access.catalog, work.budget_s)
    return new_server("bagmcp-analysis", purpose=PURPOSE, tools=tools, guard=guard, ingest=ingest)
