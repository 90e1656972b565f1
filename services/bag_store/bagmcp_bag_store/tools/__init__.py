"""The bag-store's MCP server: its tool classes and declared tools, in the order their tools are listed."""

from __future__ import annotations

from mcp.server.mcpserver import MCPServer

from bagmcp_bag_store.job_kinds import RUN_JOB
from bagmcp_bag_store.queries.page_cursor import cursor_key
from bagmcp_bag_store.tools.catalog_tools import CatalogTools
from bagmcp_bag_store.tools.fleet_tools import FIND, QUERY, views_resource
from bagmcp_bag_store.tools.message_tools import MessageTools
from bagmcp_bag_store.tools.search_tools import FILTER, SEARCH
from bagmcp_bag_store.tools.store import Store
from bagmcp_kit.declared import ServiceTools
from bagmcp_kit.ingest_wait import IngestWait
from bagmcp_kit.longwork import LongWork
from bagmcp_kit.server import McpGuard, new_server

PURPOSE = "Robot bags: list them, inspect topics, read and search messages, cut new bags, query across bags."
BAG_STORE = ServiceTools[Store]("bag_store", RUN_JOB, (SEARCH, FILTER, QUERY, FIND))


def build_server(store: Store, work: LongWork, *, guard: McpGuard | None = None) -> MCPServer:
    access, budget_bytes = store.access, store.budget_bytes
    tools = [
        CatalogTools(access, budget_bytes=budget_bytes),
        MessageTools(access, budget_bytes=budget_bytes, cursor_key=cursor_key(guard.service_token if guard else None)),
        *BAG_STORE.specs(store, work),
    ]
    ingest = IngestWait(access.catalog, work.budget_s)
    server = new_server("bagmcp-bag-store", purpose=PURPOSE, tools=tools, guard=guard, ingest=ingest)
    views_resource(server)
    return server
