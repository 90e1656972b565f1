"""The bag-store's MCP server: its tool classes, in the order their tools are listed."""

from __future__ import annotations

from mcp.server.mcpserver import MCPServer

from bagmcp_bag_store.fleet.service import Fleet
from bagmcp_bag_store.query.page_cursor import cursor_key
from bagmcp_bag_store.tools.catalog_tools import CatalogTools
from bagmcp_bag_store.tools.fleet_tools import FleetTools, views_resource
from bagmcp_bag_store.tools.message_tools import MessageTools
from bagmcp_bag_store.tools.search_tools import SearchTools
from bagmcp_kit.ingest_wait import IngestWait
from bagmcp_kit.longwork import LongWork
from bagmcp_kit.server import Guard, new_server
from bagmcp_shared.access import BagAccess

PURPOSE = "Robot bags: list them, inspect topics, read and search messages, cut new bags, query across bags."


def build_server(
    access: BagAccess, work: LongWork, fleet: Fleet, *, budget_bytes: int, guard: Guard | None = None
) -> MCPServer:
    tools = [
        CatalogTools(access, budget_bytes=budget_bytes),
        MessageTools(access, budget_bytes=budget_bytes, cursor_key=cursor_key(guard.service_token if guard else None)),
        SearchTools(access, work),
        FleetTools(fleet, work),
    ]
    ingest = IngestWait(access.catalog, work.budget_s)
    server = new_server("bagmcp-bag-store", purpose=PURPOSE, tools=tools, guard=guard, ingest=ingest)
    views_resource(server)
    return server
