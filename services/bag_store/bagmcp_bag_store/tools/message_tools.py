"""MCP adapters for reading messages: get_message_at_time, get_messages_in_range."""

from __future__ import annotations

from typing import Annotated, Literal

from mcp.types import CallToolResult
from pydantic import Field

from bagmcp_bag_store.queries import messages
from bagmcp_bag_store.queries.column_range import messages_as_columns
from bagmcp_bag_store.queries.page_cursor import CursorSigner
from bagmcp_bag_store.reports import MessageAtTime, MessageRange
from bagmcp_kit.answers import run_query
from bagmcp_kit.arguments import READ_ONLY, BagRef, Fields, TimeArg, TopicName
from bagmcp_kit.toolsets import tool
from bagmcp_shared.access import BagAccess

DEFAULT_POINTS = 1000


class MessageTools:
    def __init__(self, access: BagAccess, *, budget_bytes: int, cursor_key: bytes) -> None:
        self._access = access
        self._budget = budget_bytes
        self._cursors = CursorSigner(cursor_key)

    @tool(READ_ONLY)
    def get_message_at_time(
        self, bag: BagRef, topic: TopicName, time: TimeArg, fields: Fields = None
    ) -> Annotated[CallToolResult, MessageAtTime]:
        """The message of a topic nearest a time (log time), and how far it is from that time.
        Example: topic="/odom", time=12.5."""
        return run_query(
            lambda: messages.get_message_at_time(self._access, bag, topic, time, fields, budget_bytes=self._budget),
            lambda r: f"{r.topic} at {r.message.time.offset_s:.3f} s ({r.delta_s:+.3f} s from the requested time)",
        )

    @tool(READ_ONLY)
    def get_messages_in_range(
        self,
        bag: BagRef,
        topic: TopicName,
        start: TimeArg | None = None,
        end: TimeArg | None = None,
        fields: Fields = None,
        max_messages: Annotated[int, Field(ge=1, le=1000, description="page size")] = 20,
        cursor: Annotated[str | None, Field(description="next_cursor of the previous page")] = None,
        every: Annotated[int, Field(ge=1, description="keep every n-th message")] = 1,
        layout: Literal["messages", "columns"] = "messages",
        max_points: Annotated[
            int | None, Field(ge=2, le=5000, description="thin numeric fields to this, extremes kept (columns)")
        ] = None,
    ) -> Annotated[CallToolResult, MessageRange]:
        """Messages of a topic in a window, oldest first, in pages (next_cursor); layout=columns gives
        compact arrays of numeric `fields` (max_points with fields implies it). Example: topic="/odom",
        layout="columns"."""
        if layout == "columns" or max_points is not None:
            return run_query(
                lambda: messages_as_columns(
                    self._access,
                    bag,
                    topic,
                    start,
                    end,
                    fields or [],
                    every=every,
                    max_points=max_points or DEFAULT_POINTS,
                    budget_bytes=self._budget,
                    asked_messages=layout == "messages",
                ),
                lambda r: (
                    f"{r.returned} points of {r.total} messages of {r.topic}"
                    + (" (thinned, extremes kept)" if r.downsampled else "")
                ),
            )
        return run_query(
            lambda: messages.get_messages_in_range(
                self._access,
                bag,
                topic,
                start,
                end,
                fields,
                max_messages,
                cursor,
                every=every,
                budget_bytes=self._budget,
                signer=self._cursors,
            ),
            lambda r: (
                f"{r.returned} of {r.total} messages of {r.topic}"
                + (" (truncated; pass next_cursor for more)" if r.truncated else "")
            ),
        )
