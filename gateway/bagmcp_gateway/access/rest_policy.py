"""REST reads under the same policy as MCP: each /api/v1 route names the tools that give the same data, and a
caller may use the route only when its profile, allow/deny lists and the gateway's enable list let it call at
least one of them. So a token made with ``--deny 'plot_*'`` cannot download plot images, and one made with
``--allow bag_info`` cannot list or download bags over REST. Every tool named here belongs to the service that
serves the route, so a token that may call none of a service's tools reads none of its REST data.

Checked once, in the gateway's REST guard (auth.py), for the proxied routes of a team and the embedded routes
of ``bagmcp serve`` alike; a route this table does not name is refused to any restricted token."""

from __future__ import annotations

import re
from collections.abc import Collection
from dataclasses import dataclass
from fnmatch import fnmatchcase


@dataclass(frozen=True)
class RestRoute:
    """``tools`` (globs): calling any one of them gives the route's data; None: the scope alone decides."""

    method: str
    path: re.Pattern[str]
    tools: tuple[str, ...] | None
    why: str


def _route(method: str, path: str, tools: tuple[str, ...] | None, why: str) -> RestRoute:
    return RestRoute(method, re.compile(f"/api/v1/{path}"), tools, why)


_REF = r"[^/]+"
REST_ROUTES: tuple[RestRoute, ...] = (
    _route("GET", "bags", ("list_bags", "find_bags", "query_bags"), "each lists the library"),
    _route("GET", f"bags/{_REF}", ("bag_info", "list_bags"), "each shows a bag's record"),
    _route("GET", f"bags/{_REF}/download", ("get_messages_in_range", "filter_bag"), "each gives every message"),
    _route("GET", "artifacts/.+", ("plot_*", "compare_runs"), "the plotting tools make the artifacts"),
    _route("GET", "query", ("query_bags",), "the same SQL over the same views"),
    _route("POST", "bags", None, "no tool uploads: the upload scope decides"),
    _route("DELETE", f"bags/{_REF}", None, "no tool deletes: the delete scope decides"),
    _route("GET|POST|DELETE", "tokens(/.*)?", None, "token administration: the admin scope decides"),
    _route("GET", "session", None, "the token's own name and scopes"),
    _route("GET|POST", "lab(/.*)?", None, "the Lab calls /mcp with the caller's token, checked there"),
)


def route_for(method: str, path: str) -> RestRoute | None:
    """The table's row for ``method path`` (a path under /api/v1), or None when the table does not name it."""
    for row in REST_ROUTES:
        if method in row.method.split("|") and row.path.fullmatch(path):
            return row
    return None


def rest_refusal(method: str, path: str, callable_tools: Collection[str] | None) -> str | None:
    """Why a caller that may call ``callable_tools`` (None: every tool) may not use ``method path``, or None."""
    if callable_tools is None or not path.startswith("/api/v1/"):
        return None
    row = route_for(method, path)
    shown = path if len(path) <= 120 else f"{path[:120]}..."
    if row is None:
        return f"{shown} is not open to this token: its profile or allow/deny lists restrict it to some tools"
    if row.tools is None or any(fnmatchcase(name, glob) for name in callable_tools for glob in row.tools):
        return None
    return (
        f"this token may not read {shown}: it needs one of the tools {', '.join(row.tools)} ({row.why}), "
        "which its profile or allow/deny lists do not enable; ask an admin for a token that has one"
    )
