"""MCP adapters for long work: search_messages and filter_bag (inline when small, else a job)."""

from __future__ import annotations

from typing import Annotated, Literal

from mcp.server.mcpserver import Context
from mcp.types import CallToolResult
from pydantic import Field, JsonValue

from bagmcp_bag_store.job_kinds import FILTER, SEARCH, FilterParams, SearchParams
from bagmcp_bag_store.query.conditions import Condition
from bagmcp_bag_store.query.search import search_if_small
from bagmcp_bag_store.results import FilterResult, SearchResult
from bagmcp_kit.answers import tool_errors
from bagmcp_kit.arguments import READ_ONLY, WRITES, BagRef, TimeArg, TopicName, params_of
from bagmcp_kit.jobs import LongAnswer
from bagmcp_kit.longwork import LongWork
from bagmcp_kit.toolsets import BagTools, tool
from bagmcp_shared.access import BagAccess

Format = Literal["ros1", "ros2-sqlite3", "ros2-mcap", "mcap-json"]  # OutputFormat's values, inline in the schema
ConditionValue = Annotated[
    JsonValue,
    Field(description="number, text, [low, high] (between) or {x, y, radius} m (near_position)"),
]


def _search_summary(result: SearchResult) -> str:
    closest = f"; closest approach {result.closest.distance_m:.3f} m" if result.closest else ""
    if result.condition in ("max", "min") and result.matches:
        peak = result.matches[0]
        value = f"{peak.value:.6g}" if isinstance(peak.value, float) else str(peak.value)
        return (
            f"{result.condition} {result.field} = {value} first at {peak.time.offset_s:.3f} s; "
            f"{result.total} of {result.scanned} messages have it"
        )
    return f"{result.total} of {result.scanned} messages match{closest}"


def _filter_summary(result: FilterResult) -> str:
    existed = "" if result.created else " (it existed already)"
    note = f"; {result.note}" if result.note else ""
    return f"bag {result.name} ({result.bag_id}) with {result.message_count} messages{existed}{note}"


class SearchTools(BagTools):
    def __init__(self, access: BagAccess, work: LongWork, *, budget_bytes: int) -> None:
        super().__init__(access, work)
        self._budget_bytes = budget_bytes

    @tool(READ_ONLY)
    async def search_messages(
        self,
        ctx: Context,
        bag: BagRef,
        topic: TopicName,
        condition: Condition,
        value: ConditionValue = None,
        field: Annotated[str | None, Field(description="path to test (default: the obvious one)")] = None,
        start: TimeArg | None = None,
        end: TimeArg | None = None,
        limit: Annotated[int, Field(ge=1, le=200, description="matches to show")] = 20,
        correlate_topic: Annotated[str | None, Field(description="add its nearest message (or /topic.path)")] = None,
        correlate_tolerance_s: Annotated[float, Field(gt=0, le=60, description="max time apart")] = 0.1,
    ) -> Annotated[CallToolResult, LongAnswer[SearchResult]]:
        """Messages meeting a condition: count, first matches (max/min: where a field peaks),
        closest approach for near_position. Example: topic=/odom, condition=near_position,
        value={"x":1,"y":-2,"radius":0.5}."""
        with tool_errors():
            params = params_of(
                SearchParams,
                bag=bag,
                topic=topic,
                condition=condition,
                value=value,
                field=field,
                start=start,
                end=end,
                limit=limit,
                correlate_topic=correlate_topic,
                correlate_tolerance_s=correlate_tolerance_s,
            )
        return await self._work.run(
            ctx,
            SEARCH,
            params,
            _search_summary,
            inline=lambda p: search_if_small(self._access, p, budget_bytes=self._budget_bytes),
        )

    @tool(WRITES)
    async def filter_bag(
        self,
        ctx: Context,
        bag: BagRef,
        name: Annotated[str | None, Field(description="name of the new bag")] = None,
        include_topics: Annotated[list[str] | None, Field(description="keep only these")] = None,
        exclude_topics: Annotated[list[str] | None, Field(description="drop these")] = None,
        start: TimeArg | None = None,
        end: TimeArg | None = None,
        rates: Annotated[dict[str, float] | None, Field(description="max Hz per topic, e.g. {'/scan': 2}")] = None,
        format: Annotated[Format | None, Field(description="default: the source's")] = None,
    ) -> Annotated[CallToolResult, LongAnswer[FilterResult]]:
        """A new bag from some topics, a time window and/or rate limits, stored under `name` (the same request
        gives the same bag; needs the upload scope). Example: include_topics=["/cmd_vel", "/odom"]."""
        with tool_errors():
            params = params_of(
                FilterParams,
                bag=bag,
                name=name,
                include_topics=include_topics,
                exclude_topics=exclude_topics,
                start=start,
                end=end,
                rates=rates,
                format=format,
            )
        return await self._work.run(ctx, FILTER, params, _filter_summary)
