"""The bag-store's MCP server: its tools, registered in one place."""

from __future__ import annotations

from mcp.server.mcpserver import MCPServer

from bagmcp_bag_store.tools.catalog_tools import CatalogTools
from bagmcp_bag_store.tools.message_tools import MessageTools
from bagmcp_bag_store.tools.search_tools import SearchTools
from bagmcp_kit.arguments import READ_ONLY, WRITES, ToolSpec, register
from bagmcp_kit.longwork import LongWork
from bagmcp_kit.server import new_server
from bagmcp_shared.access import BagAccess

PURPOSE = "Robot bags: list them, inspect topics, read and search messages, cut new bags."


def build_server(
    access: BagAccess,
    work: LongWork,
    *,
    budget_bytes: int,
    service_token: str | None = None,
    public_url: str = "http://127.0.0.1:8001",
) -> MCPServer:
    server = new_server("bagmcp-bag-store", purpose=PURPOSE, service_token=service_token, public_url=public_url)
    catalog = CatalogTools(access, budget_bytes=budget_bytes)
    reading = MessageTools(access, budget_bytes=budget_bytes)
    searching = SearchTools(access, work)
    register(
        server,
        [
            ToolSpec(catalog.list_bags, READ_ONLY),
            ToolSpec(catalog.bag_info, READ_ONLY),
            ToolSpec(catalog.describe_topic, READ_ONLY),
            ToolSpec(reading.get_message_at_time, READ_ONLY),
            ToolSpec(reading.get_messages_in_range, READ_ONLY),
            ToolSpec(searching.search_messages, READ_ONLY),
            ToolSpec(searching.filter_bag, WRITES),
        ],
    )
    return server
