"""The bag-store's MCP tools: thin adapters over queries.py; BagmcpError becomes a tool error here."""

from __future__ import annotations

from collections.abc import Callable
from typing import Annotated, TypeVar, cast

from mcp.server.auth.provider import TokenVerifier
from mcp.server.auth.settings import AuthSettings
from mcp.server.mcpserver import Context, MCPServer
from mcp.server.mcpserver.exceptions import ToolError
from mcp.types import CallToolResult, TextContent, ToolAnnotations
from pydantic import BaseModel, Field, JsonValue

from bagmcp_bag_store import longwork, messages, queries
from bagmcp_bag_store.conditions import Condition, check_value
from bagmcp_bag_store.deps import BagStoreDeps
from bagmcp_bag_store.jobs import Job
from bagmcp_bag_store.results import (
    BagInfo,
    BagList,
    FilterAnswer,
    FilterResult,
    JobInfo,
    MessageAtTime,
    MessageRange,
    SearchAnswer,
    SearchResult,
    TopicDescription,
)
from bagmcp_shared.errors import BagmcpError

M = TypeVar("M", bound=BaseModel)
WRITES = ToolAnnotations(read_only_hint=False, destructive_hint=False, idempotent_hint=True, open_world_hint=False)
READ_ONLY = ToolAnnotations(read_only_hint=True, destructive_hint=False, idempotent_hint=True, open_world_hint=False)
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


def _job_answer(job: Job, answer: type[M], result: type[BaseModel], done: Callable[[M], str]) -> CallToolResult:
    """The tool's answer for a job: its result when it finished in time, else the job to follow."""
    if job.state == "failed":
        raise ToolError(job.error or "the job failed")
    if job.state == "cancelled":
        raise ToolError(f"job {job.id} was cancelled")
    finished = job.state == "succeeded" and job.result is not None
    model = answer.model_validate(
        {
            "job": longwork.job_info(job).model_copy(update={"result": None}),
            "result": result.model_validate(job.result) if finished else None,
        }
    )
    text = (
        done(model)
        if finished
        else (
            f"still {job.state} after the time budget ({job.progress:.0%}: {job.message}); "
            f"call get_job with job_id {job.id} to follow it, or cancel_job to stop it"
        )
    )
    return CallToolResult(
        content=[TextContent(type="text", text=f"{text}\n{model.model_dump_json()}")],
        structured_content=model.model_dump(mode="json"),
    )


def _search_summary(answer: SearchAnswer) -> str:
    result = answer.result
    assert result is not None
    closest = f"; closest approach {result.closest.distance_m:.3f} m" if result.closest else ""
    return f"{result.total} of {result.scanned} messages match{closest}"


def _filter_summary(answer: FilterAnswer) -> str:
    result = answer.result
    assert result is not None
    existed = "" if result.created else " (it existed already)"
    return f"bag {result.name} ({result.bag_id}) with {result.message_count} messages{existed}"


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
            lambda r: f"{r.name}: {r.message_count} messages on {len(r.topics)} topics over {r.duration_s:.3f} s",
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
            lambda: messages.get_message_at_time(deps, bag, topic, time, fields),
            lambda r: f"{r.topic} at {r.message.time.offset_s:.3f} s ({r.delta_s:+.3f} s from the requested time)",
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
            lambda: messages.get_messages_in_range(deps, bag, topic, start, end, fields, max_messages, cursor),
            lambda r: (
                f"{r.returned} of {r.total} messages of {r.topic}"
                + (" (truncated; pass next_cursor for more)" if r.truncated else "")
            ),
        )

    @mcp.tool(annotations=READ_ONLY)
    async def search_messages(
        ctx: Context,
        bag: BagRef,
        topic: TopicName,
        condition: Condition,
        value: Annotated[
            JsonValue,
            Field(
                description=(
                    "number for greater_than/less_than/equals; [low, high] for between; text for contains "
                    "(case-insensitive), regex and equals; {x, y, radius} in metres (or 'x,y,radius') for "
                    "near_position; omitted for field_exists"
                )
            ),
        ] = None,
        field: Annotated[
            str | None,
            Field(
                description=(
                    "message path to test, e.g. twist.twist.linear.x; default: the type's obvious number for "
                    "numeric conditions, all text fields for text conditions, the pose position for near_position"
                )
            ),
        ] = None,
        start: TimeArg | None = None,
        end: TimeArg | None = None,
        limit: Annotated[int, Field(ge=1, le=200)] = 20,
        correlate_topic: Annotated[str | None, Field(description="attach the nearest message of this topic")] = None,
        correlate_tolerance: Annotated[float, Field(gt=0, le=60, description="seconds")] = 0.1,
    ) -> Annotated[CallToolResult, SearchAnswer]:
        """Find messages of a topic that meet a condition: contains, regex, equals, not_equals,
        greater_than, less_than, between, near_position, field_exists. Gives the total count, the
        first matches with their times, and for near_position the closest approach (distance,
        position, time) even when nothing came within the radius. Optionally attaches to each
        match the nearest message of correlate_topic. Long searches answer with a job (get_job)."""
        try:
            check_value(condition, value)
        except BagmcpError as err:
            raise ToolError(str(err)) from err
        params: dict[str, JsonValue] = {
            "bag": bag,
            "topic": topic,
            "condition": condition,
            "value": value,
            "field": field,
            "start": start,
            "end": end,
            "limit": limit,
            "correlate_topic": correlate_topic,
            "correlate_tolerance": correlate_tolerance,
        }
        job = await longwork.start_and_wait(deps, ctx, "search", params)
        return _job_answer(job, SearchAnswer, SearchResult, _search_summary)

    @mcp.tool(annotations=WRITES)
    async def filter_bag(
        ctx: Context,
        bag: BagRef,
        name: Annotated[str | None, Field(description="name of the new bag (default: derived)")] = None,
        include_topics: Annotated[list[str] | None, Field(description="keep only these topics")] = None,
        exclude_topics: Annotated[list[str] | None, Field(description="drop these topics")] = None,
        start: TimeArg | None = None,
        end: TimeArg | None = None,
        rates: Annotated[
            dict[str, float] | None, Field(description="max rate per topic in Hz, e.g. {'/scan': 2}")
        ] = None,
        format: Annotated[
            str | None, Field(description="ros1, ros2-sqlite3 or ros2-mcap (default: same family)")
        ] = None,
    ) -> Annotated[CallToolResult, FilterAnswer]:
        """Write a new bag with a subset of topics, a time window and/or per-topic rate limits, keeping
        message definitions and QoS/latching, and add it to the store under `name` (an existing name is
        an error). The same request twice gives the same bag. Long writes answer with a job (get_job)."""
        params: dict[str, JsonValue] = {
            "bag": bag,
            "name": name,
            "include_topics": cast(JsonValue, include_topics),
            "exclude_topics": cast(JsonValue, exclude_topics),
            "start": start,
            "end": end,
            "rates": cast(JsonValue, rates),
            "format": format,
        }
        job = await longwork.start_and_wait(deps, ctx, "filter", params)
        return _job_answer(job, FilterAnswer, FilterResult, _filter_summary)

    @mcp.tool(annotations=READ_ONLY)
    def get_job(ctx: Context, job_id: str) -> Annotated[CallToolResult, JobInfo]:
        """State (queued, running, succeeded, failed, cancelled), progress (0..1 with a message) and, once
        succeeded, the result of a job started by search_messages or filter_bag."""
        return _answer(
            lambda: longwork.get_job(deps, ctx, job_id),
            lambda j: f"job {j.job_id}: {j.state} ({j.progress:.0%}) {j.message}",
        )

    @mcp.tool(annotations=WRITES)
    def cancel_job(ctx: Context, job_id: str) -> Annotated[CallToolResult, JobInfo]:
        """Stop a running or queued job; it ends in state cancelled and keeps nothing half-done."""
        return _answer(
            lambda: longwork.cancel_job(deps, ctx, job_id),
            lambda j: f"job {j.job_id}: {j.state}; {j.message}",
        )

    return mcp
