"""The declarations of the questions across bags: query_bags (SQL) and find_bags (typed conditions), and the
views as a resource. Each caller sees the views its token's tools would show (fleet/views.py)."""

from __future__ import annotations

from typing import Any

from mcp.server.mcpserver import Context, MCPServer

from bagmcp_bag_store.fleet.answers import QueryAnswer, text_table
from bagmcp_bag_store.fleet.find import FindAnswer
from bagmcp_bag_store.fleet.find_params import FindParams, QueryParams
from bagmcp_bag_store.fleet.views import VIEWS, views_for
from bagmcp_bag_store.tools.store import Store
from bagmcp_kit.declared import Declared
from bagmcp_kit.identity import callable_tools

VIEWS_URI = "bagmcp://fleet/views"
_SERIES = ("bag", "bag_id", "topic", "t", "offset_s", "first_t", "last_t", "file", "function", "line")


def _compact(name: str) -> str:
    columns = [c for c in VIEWS[name].names if c not in _SERIES or (name == "topics" and c == "topic")]
    return f"{name}({','.join(columns)})"


def _find_summary(answer: FindAnswer) -> str:
    shown = "; ".join(f"{m.bag}: " + " / ".join(e.detail for e in m.evidence) for m in answer.matches[:5])
    return f"{answer.total} of {answer.bags_queried} bags match" + (f": {shown}" if shown else "")


def _readable(ctx: Context, store: Store) -> dict[str, Any]:
    return {"readable": views_for(callable_tools(ctx))}


def _query_given(ctx: Context, store: Store) -> dict[str, Any]:
    return _readable(ctx, store) | {"max_rows": store.fleet.engine.limits.max_rows}


QUERY = Declared(
    "query_bags",
    "Read-only DuckDB SQL (one SELECT) over all bags. Views (all have bag; series: topic, t epoch s, "
    "offset_s): " + " ".join(_compact(n) for n in VIEWS) + f". Units: {VIEWS_URI}. "
    "Example: SELECT bag, max(speed) FROM poses GROUP BY bag",
    QueryParams,
    QueryAnswer,
    lambda store, p, progress: store.fleet.query(p, progress),
    text_table,
    small=lambda store, p: store.fleet.query_is_small(p),
    job="query",
    given=_query_given,
)
FIND = Declared(
    "find_bags",
    "Bags meeting ALL conditions given, with evidence (when, how much); topic scopes gap_above. "
    'Example: log_level="ERROR", near=[3, -1, 0.5]',
    FindParams,
    FindAnswer,
    lambda store, p, progress: store.fleet.find(p, progress),
    _find_summary,
    small=lambda store, p: store.fleet.find_is_small(p),
    job="find",
    given=_readable,
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
