"""MCP adapters for catalog and type questions: list_bags, bag_info, describe_topic."""

from __future__ import annotations

from typing import Annotated

from mcp.types import CallToolResult
from pydantic import Field

from bagmcp_bag_store.queries import catalog_queries
from bagmcp_bag_store.reports import BagInfo, BagList, TopicDescription
from bagmcp_kit.answers import run_query
from bagmcp_kit.arguments import READ_ONLY, BagRef, Offset, TopicName
from bagmcp_kit.toolsets import tool
from bagmcp_shared.access import BagAccess
from bagmcp_shared.wording import counted


class CatalogTools:
    def __init__(self, access: BagAccess, *, budget_bytes: int) -> None:
        self._access = access
        self._budget = budget_bytes

    @tool(READ_ONLY)
    def list_bags(
        self,
        name: Annotated[str | None, Field(description="part of the name")] = None,
        tag: Annotated[str | None, Field(description="with this tag")] = None,
        offset: Offset = 0,
        limit: Annotated[int, Field(ge=1, le=500, description="page size")] = 50,
    ) -> Annotated[CallToolResult, BagList]:
        """Bags in the store: status (ready, ingesting, or failed and why), format, duration, counts. Call this
        first. Example: name="husky"."""
        return run_query(
            lambda: catalog_queries.list_bags(self._access.catalog, name=name, tag=tag, offset=offset, limit=limit),
            lambda r: f"{counted(r.total, 'bag')}; showing {len(r.bags)} from {r.offset}",
        )

    @tool(READ_ONLY)
    def bag_info(self, bag: BagRef) -> Annotated[CallToolResult, BagInfo]:
        """One bag: format, size, start/end, duration, each topic's type, count and rate (odd rates explained).
        Example: bag="run1"."""
        return run_query(
            lambda: catalog_queries.bag_info(self._access.catalog, bag),
            lambda r: f"{r.name}: {r.message_count} messages on {len(r.topics)} topics over {r.duration_s:.3f} s",
        )

    @tool(READ_ONLY)
    def describe_topic(self, bag: BagRef, topic: TopicName) -> Annotated[CallToolResult, TopicDescription]:
        """A topic's field paths with types and units, plus its first message as a sample; use the paths in
        `fields` and plots. Example: topic="/odom"."""
        return run_query(
            lambda: catalog_queries.describe_topic(self._access, bag, topic, budget_bytes=self._budget),
            lambda r: f"{r.topic} ({r.type}): {r.count} messages, {len(r.fields)} fields",
        )
