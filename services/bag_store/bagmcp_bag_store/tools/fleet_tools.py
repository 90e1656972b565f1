"""MCP adapters for questions across bags: query_bags (SQL) and find_bags (typed conditions), and the views
as a resource. Each caller sees the views its token's tools would show (fleet/views.py)."""

from __future__ import annotations

from typing import Annotated

from mcp.server.mcpserver import Context, MCPServer
from mcp.types import CallToolResult
from pydantic import Field

from bagmcp_bag_store.fleet.answers import QueryAnswer, text_table
from bagmcp_bag_store.fleet.find import FindAnswer
from bagmcp_bag_store.fleet.find_params import FindParams, LogLevel, QueryParams
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
_SERIES = ("bag", "bag_id", "topic", "t", "offset_s", "first_t", "last_t", "file", "function", "line")


def _compact(name: str) -> str:
    columns = [c for c in VIEWS[name].names if c not in _SERIES or (name == "topics" and c == "topic")]
    return f"{name}({','.join(columns)})"


def _find_summary(answer: FindAnswer) -> str:
    shown = "; ".join(f"{m.bag}: " + " / ".join(e.detail for e in m.evidence) for m in answer.matches[:5])
    return f"{answer.total} of {answer.bags_queried} bags match" + (f": {shown}" if shown else "")


class FleetTools:
    def __init__(self, fleet: Fleet, work: LongWork) -> None:
        self._fleet = fleet
        self._work = work

    @tool(READ_ONLY)
    async def query_bags(
        self, ctx: Context, sql: Annotated[str, Field(description="one SELECT")]
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
        topic: Annotated[str | None, Field(description="has it")] = None,
        type: Annotated[str | None, Field(description="has one")] = None,
        between: Annotated[list[float | str] | None, Field(description="recorded: [from, to] epoch s/ISO")] = None,
        log_level: Annotated[LogLevel | None, Field(description="at or above")] = None,
        log_node: Annotated[str | None, Field(description="part")] = None,
        log_text: Annotated[str | None, Field(description="part")] = None,
        speed_above: Annotated[float | None, Field(description="m/s")] = None,
        near: Annotated[list[float] | None, Field(description="[x, y, radius] m")] = None,
        scan_below: Annotated[float | None, Field(description="m")] = None,
        gap_above: Annotated[float | None, Field(description="s")] = None,
    ) -> Annotated[CallToolResult, LongAnswer[FindAnswer]]:
        """Bags meeting ALL conditions given, with evidence (when, how much); topic scopes gap_above.
        Example: log_level="ERROR", near=[3, -1, 0.5]"""
        readable = views_for(callable_tools(ctx))
        with tool_errors():
            params = params_of(
                FindParams,
                topic=topic,
                type=type,
                between=between,
                log_level=log_level,
                log_node=log_node,
                log_text=log_text,
                speed_above=speed_above,
                near=near,
                scan_below=scan_below,
                gap_above=gap_above,
                readable=readable,
            )
        return await self._work.run(ctx, FIND, params, _find_summary, small=self._fleet.find_is_small)


FleetTools.query_bags.__doc__ = (
    "Read-only DuckDB SQL (one SELECT) over all bags. Views (all have bag; series: topic, t epoch s, "
    "offset_s): " + " ".join(_compact(n) for n in VIEWS) + f". Units: {VIEWS_URI}. "
    "Example: SELECT bag, max(speed) FROM poses GROUP BY bag"
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
