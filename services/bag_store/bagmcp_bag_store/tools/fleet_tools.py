"""MCP adapters for questions across bags: query_bags (SQL) and find_bags (typed conditions), and the views
as a resource. Each caller sees the views its token's tools would show (fleet/views.py)."""

from __future__ import annotations

from typing import Annotated

from mcp.server.mcpserver import Context, MCPServer
from mcp.types import CallToolResult
from pydantic import Field

from bagmcp_bag_store.fleet.answers import QueryAnswer, text_table
from bagmcp_bag_store.fleet.find import FindAnswer
from bagmcp_bag_store.fleet.find_params import FindParams, LogLevel, Near, QueryParams
from bagmcp_bag_store.fleet.service import Fleet
from bagmcp_bag_store.fleet.views import VIEWS, views_for
from bagmcp_bag_store.job_kinds import FIND, QUERY
from bagmcp_kit.answers import tool_errors
from bagmcp_kit.arguments import READ_ONLY, params_of
from bagmcp_kit.identity import callable_tools
from bagmcp_kit.jobs import LongAnswer
from bagmcp_kit.longwork import LongWork
from bagmcp_kit.toolsets import tool

VIEWS_URI = "bagmcp://fleet/views"
_SERIES = ("bag", "bag_id", "topic", "t", "offset_s")


def _compact(name: str) -> str:
    columns = [c for c in VIEWS[name].names if c not in _SERIES]
    return f"{name}({', '.join(columns)})"


def _find_summary(answer: FindAnswer) -> str:
    shown = "; ".join(f"{m.bag}: " + " / ".join(e.detail for e in m.evidence) for m in answer.matches[:5])
    return f"{answer.total} of {answer.bags_queried} bags match" + (f": {shown}" if shown else "")


class FleetTools:
    def __init__(self, fleet: Fleet, work: LongWork) -> None:
        self._fleet = fleet
        self._work = work

    @tool(READ_ONLY)
    async def query_bags(
        self, ctx: Context, sql: Annotated[str, Field(description="one DuckDB SELECT over the views")]
    ) -> Annotated[CallToolResult, LongAnswer[QueryAnswer]]:
        """(set below from the views)"""
        readable = views_for(callable_tools(ctx))
        with tool_errors():
            params = params_of(QueryParams, sql=sql, readable=readable, max_rows=self._fleet.engine.limits.max_rows)
        return await self._work.run(ctx, QUERY, params, text_table, small=self._fleet.query_is_small)

    @tool(READ_ONLY)
    async def find_bags(
        self,
        ctx: Context,
        has_topic: Annotated[str | None, Field(description="e.g. /scan")] = None,
        has_type: Annotated[str | None, Field(description="e.g. sensor_msgs/LaserScan")] = None,
        recorded_after: Annotated[float | str | None, Field(description="epoch s or ISO")] = None,
        recorded_before: Annotated[float | str | None, Field(description="epoch s or ISO")] = None,
        log_level: Annotated[LogLevel | None, Field(description="a log at or above it")] = None,
        log_node: Annotated[str | None, Field(description="log from a node (substring)")] = None,
        log_text: Annotated[str | None, Field(description="log text containing this")] = None,
        speed_above_mps: Annotated[float | None, Field(ge=0, description="a pose faster than this")] = None,
        near: Annotated[Near | None, Field(description="came within radius_m of (x, y)")] = None,
        scan_below_m: Annotated[float | None, Field(gt=0, description="a scan's closest range below")] = None,
        gap_longer_than_s: Annotated[float | None, Field(gt=0, description="a topic silent longer")] = None,
        gap_topic: Annotated[str | None, Field(description="only this topic's gaps")] = None,
        limit: Annotated[int, Field(ge=1, le=500, description="bags to show")] = 50,
    ) -> Annotated[CallToolResult, LongAnswer[FindAnswer]]:
        """Bags meeting ALL the conditions given, each with evidence (when, how much), across every bag.
        Example: log_level="ERROR", log_node="planner", near={"x": 3, "y": -1, "radius_m": 0.5}."""
        readable = views_for(callable_tools(ctx))
        with tool_errors():
            params = params_of(
                FindParams,
                has_topic=has_topic,
                has_type=has_type,
                recorded_after=recorded_after,
                recorded_before=recorded_before,
                log_level=log_level,
                log_node=log_node,
                log_text=log_text,
                speed_above_mps=speed_above_mps,
                near=near,
                scan_below_m=scan_below_m,
                gap_longer_than_s=gap_longer_than_s,
                gap_topic=gap_topic,
                limit=limit,
                readable=readable,
            )
        return await self._work.run(ctx, FIND, params, _find_summary, small=self._fleet.find_is_small)


FleetTools.query_bags.__doc__ = (
    "Read-only SQL (DuckDB, one SELECT or WITH...SELECT) across every bag. Views: "
    + "; ".join(_compact(n) for n in VIEWS)
    + ". Time views also have bag, topic, t (epoch s), offset_s (s from bag start); topics/tf_edges have bag. "
    f"Limits: time, memory, rows (total and truncated given). Columns and units: resource {VIEWS_URI}. "
    "Example: SELECT bag, max(speed) FROM poses GROUP BY bag ORDER BY 2 DESC"
)


def views_resource(server: MCPServer) -> None:
    """The views, their columns with types and meanings, as an MCP resource."""

    @server.resource(VIEWS_URI, name="fleet-views", description="query_bags' views and columns", mime_type="text/plain")
    def read_views() -> str:
        lines = []
        for view in VIEWS.values():
            lines.append(f"{view.name}: {view.doc}")
            lines.extend(f"  {c.name} {c.type}{'  ' + c.doc if c.doc else ''}" for c in view.columns)
        return "\n".join(lines)
