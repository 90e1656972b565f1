"""The analysis service's MCP server: its tools, registered in one place."""

from __future__ import annotations

from mcp.server.mcpserver import MCPServer

from bagmcp_analysis.tools.image_tools import ImageTools
from bagmcp_analysis.tools.motion_tools import MotionTools
from bagmcp_analysis.tools.record_tools import RecordTools
from bagmcp_kit.arguments import READ_ONLY, ToolSpec, register
from bagmcp_kit.longwork import LongWork
from bagmcp_kit.server import new_server
from bagmcp_shared.access import BagAccess

PURPOSE = "Robot bag analysis: trajectories, lidar obstacles, logs, TF frames, images, topic timing, windows."


def build_server(
    access: BagAccess, work: LongWork, *, service_token: str | None = None, public_url: str = "http://127.0.0.1:8002"
) -> MCPServer:
    server = new_server("bagmcp-analysis", purpose=PURPOSE, service_token=service_token, public_url=public_url)
    motion = MotionTools(access, work)
    records = RecordTools(access, work)
    images = ImageTools(access)
    register(
        server,
        [
            ToolSpec(motion.analyze_trajectory, READ_ONLY),
            ToolSpec(motion.analyze_lidar_scan, READ_ONLY),
            ToolSpec(records.analyze_logs, READ_ONLY),
            ToolSpec(records.get_tf_tree, READ_ONLY),
            ToolSpec(records.lookup_transform, READ_ONLY),
            ToolSpec(images.get_image_at_time, READ_ONLY),
            ToolSpec(records.topic_statistics, READ_ONLY),
            ToolSpec(motion.summarize_window, READ_ONLY),
        ],
    )
    return server
