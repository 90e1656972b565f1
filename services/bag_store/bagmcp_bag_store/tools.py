"""The bag-store's MCP tools: thin adapters over queries.py; BagmcpError becomes a tool error here."""

from __future__ import annotations

from collections.abc import Callable
from typing import Annotated, TypeVar

from mcp.server.auth.provider import TokenVerifier
from mcp.server.auth.settings import AuthSettings
from mcp.server.mcpserver import MCPServer
from mcp.server.mcpserver.exceptions import ToolError
from mcp.types import CallToolResult, TextContent, ToolAnnotations
from pydantic import BaseModel, Field

from bagmcp_bag_store import queries
from bagmcp_bag_store.deps import BagStoreDeps
from bagmcp_bag_store.results import BagInfo, BagList, MessageAtTime, MessageRange, TopicDescription
from bagmcp_shared.errors import BagmcpError

M = TypeVar("M", bound=BaseModel)
READ_ONLY = ToolAnnotations(
    read_only_hint=True, destructive_hint=False, idempotent_hint=True, open_world_hint=False
)
BagRef = Annotated[str, Field(description="Bag id, name, or a unique prefix of either (see list_bags).")]
TopicName = Annotated[str, Field(description="Topic name, e.g. /odom (leading slash optional).")]
TimeArg = Annotated[
    float | str,
    Field(description="Seconds from the bag start (numbers below 1e9), epoch seconds, or ISO-8601."),
]
Fields = Annotated[
    list[str] | None,
    Field(
        description="Message paths inside the message to return instead of the whole message, "
        "e.g. ['pose.pose.position.x', 'twist.twist.linear.x']; see describe_topic."
    ),
]


def _answer(run: Callable[[], M], summarize: Callable[[M], str]) -> CallToolResult:
    """Run a query; structured content plus a one-line summary and the JSON as text."""
    try:
        model = run()
    except BagmcpError as err:
        raise ToolError(str(err)) from err
    data = model.model_dump(mode="json")
    text = f"{summarize(model)}\n{model.model_dump_json()}"
    return CallToolResult(content=[TextContent(type="text", text=text)], structured_content=data)


def build_mcp(
    deps: BagStoreDeps, *, token_verifier: TokenVerifier | None = None, auth: AuthSettings | None = None
) -> MCPServer:
    """The bag-store MCP server with its tools bound to ``deps``."""
    mcp = MCPServer(
        "bagmcp-bag-store",
        instructions="Robot bags: list them, inspect topics, read messages.",
        token_verifier=token_verifier,
        auth=auth,
    )

    @mcp.tool(annotations=READ_ONLY)
    def list_bags(
        name: str | None = None, tag: str | None = None, offset: int = 0, limit: int = 50
    ) -> Annotated[CallToolResult, BagList]:
        """List the recorded bags in the store with format, duration, message and topic counts.

        Filter by a part of the name or by tag; results are paginated (offset/limit, next_offset).
        Call this first to find the bag to ask about.
        """
        return _answer(
            lambda: queries.list_bags(deps, name=name, tag=tag, offset=offset, limit=limit),
            lambda r: f"{r.total} bags; showing {len(r.bags)} from {r.offset}",
        )

    @mcp.tool(annotations=READ_ONLY)
    def bag_info(bag: BagRef) -> Annotated[CallToolResult, BagInfo]:
        """Summary of one bag: format, size, start/end (offset and absolute), duration, and every
        topic with its message type, count and rate. Answers from the catalog without reading the bag."""
        return _answer(
            lambda: queries.bag_info(deps, bag),
            lambda r: (
                f"{r.name}: {r.message_count} messages on {len(r.topics)} topics over {r.duration_s:.3f} s"
            ),
        )

    @mcp.tool(annotations=READ_ONLY)
    def describe_topic(bag: BagRef, topic: TopicName) -> Annotated[CallToolResult, TopicDescription]:
        """The fields of a topic's message type as message paths with types and units (where the
        type defines them), plus the first message as a sample. Use these paths in `fields`
        of other tools and in plots, e.g. twist.twist.linear.x or pose.pose.orientation.yaw."""
        return _answer(
            lambda: queries.describe_topic(deps, bag, topic),
            lambda r: f"{r.topic} ({r.type}): {r.count} messages, {len(r.fields)} fields",
        )

    @mcp.tool(annotations=READ_ONLY)
    def get_message_at_time(
        bag: BagRef, topic: TopicName, time: TimeArg, fields: Fields = None
    ) -> Annotated[CallToolResult, MessageAtTime]:
        """The message of a topic nearest to a time (by log time), with its offset from the bag
        start, absolute stamp, header stamp, and how far it is from the requested time."""
        return _answer(
            lambda: queries.get_message_at_time(deps, bag, topic, time, fields),
            lambda r: (
                f"{r.topic} at {r.message.time.offset_s:.3f} s ({r.delta_s:+.3f} s from the requested time)"
            ),
        )

    @mcp.tool(annotations=READ_ONLY)
    def get_messages_in_range(
        bag: BagRef,
        topic: TopicName,
        start: TimeArg | None = None,
        end: TimeArg | None = None,
        fields: Fields = None,
        max_messages: Annotated[int, Field(ge=1, le=1000)] = 20,
        cursor: Annotated[str | None, Field(description="next_cursor of a previous call")] = None,
    ) -> Annotated[CallToolResult, MessageRange]:
        """Messages of a topic between start and end (inclusive; whole bag when omitted), oldest
        first. Use `fields` to project message paths. Output is bounded: `total` counts the whole
        window, `truncated` and `next_cursor` continue where this page stopped."""
        return _answer(
            lambda: queries.get_messages_in_range(deps, bag, topic, start, end, fields, max_messages, cursor),
            lambda r: (
                f"{r.returned} of {r.total} messages of {r.topic}"
                + (" (truncated; pass next_cursor for more)" if r.truncated else "")
            ),
        )

    return mcp
