"""The bag-store's MCP server: its declared tools, in the order they are listed (the reading tools first)."""

from __future__ import annotations

from mcp.server.mcpserver import MCPServer

from bagmcp_bag_store.queries.page_cursor import CursorSigner, cursor_key
from bagmcp_bag_store.task_refs import RUN_JOB
from bagmcp_bag_store.tools.catalog_tools import BAG_INFO, DESCRIBE_TOPIC, LIST_BAGS
from bagmcp_bag_store.tools.fleet_tools import FIND, QUERY, views_resource
from bagmcp_bag_store.tools.message_tools import MESSAGE_AT_TIME, MESSAGES_IN_RANGE
from bagmcp_bag_store.tools.search_tools import FILTER, SEARCH
from bagmcp_bag_store.tools.store import Reading, Store
from bagmcp_kit.declared import ServiceTools, short_specs
from bagmcp_kit.ingest_wait import IngestWait
from bagmcp_kit.longwork import LongWork
from bagmcp_kit.server import McpGuard, new_server

PURPOSE = "Robot bags: list them, inspect topics, read and search messages, cut new bags, query across bags."
READING = (LIST_BAGS, BAG_INFO, DESCRIBE_TOPIC, MESSAGE_AT_TIME, MESSAGES_IN_RANGE)
BAG_STORE = ServiceTools[Store]("bag_store", RUN_JOB, (SEARCH, FILTER, QUERY, FIND))


def build_server(store: Store, work: LongWork, *, guard: McpGuard | None = None) -> MCPServer:
    cursors = CursorSigner(cursor_key(guard.service_token if guard else None))
    reading = Reading(store.access, store.budget_bytes, cursors)
    tools = [*short_specs(reading, READING), *BAG_STORE.specs(store, work)]
    ingest = IngestWait(store.access.catalog, work.budget_s)
    server = new_server("bagmcp-bag-store", purpose=PURPOSE, tools=tools, guard=guard, ingest=ingest)
    views_resource(server)
    return server
