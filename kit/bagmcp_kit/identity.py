"""Who called a tool: the gateway (which alone holds the service credential) names the caller in
the request metadata; a tool called in process without a gateway belongs to "local". For a token its
profile or allow/deny lists restrict, the gateway also names the tools it may call (answers across bags
show only what those tools would)."""

from __future__ import annotations

from typing import cast

from fastapi import Request
from mcp.server.mcpserver import Context
from mcp.types import RequestParamsMeta

OWNER_META_KEY = "bagmcp/owner"
TOOLS_META_KEY = "bagmcp/tools"
TOOLS_HEADER = "x-bagmcp-tools"  # the same list on a REST request the gateway forwards
LOCAL_CALLER = "local"


def caller(ctx: Context) -> str:
    meta = ctx.request_context.meta or {}
    owner = meta.get(OWNER_META_KEY)
    return str(owner) if owner else LOCAL_CALLER


def callable_tools(ctx: Context) -> frozenset[str] | None:
    """The tools the caller's token may call; None when it is not restricted (or no gateway is in front)."""
    meta = ctx.request_context.meta or {}
    tools = meta.get(TOOLS_META_KEY)
    return frozenset(str(t) for t in tools) if isinstance(tools, list) else None


def owner_meta(who: str, *, tools: list[str] | None = None) -> RequestParamsMeta:
    """The request metadata naming the caller (and, for a restricted token, the tools it may call), as the
    gateway sends it to a service."""
    meta: dict[str, object] = {OWNER_META_KEY: who}
    if tools is not None:
        meta[TOOLS_META_KEY] = tools
    return cast(RequestParamsMeta, meta)


def rest_callable_tools(request: Request) -> frozenset[str] | None:
    """The tools the caller of a REST route may call: as the gateway in this process found them, else as the
    gateway in front of this service forwarded them (a caller's own header never reaches a service through
    the gateway, and here it could only narrow what it sees); None when not restricted."""
    if hasattr(request.state, "bagmcp_tools"):
        found = request.state.bagmcp_tools
        return frozenset(found) if found is not None else None
    header = request.headers.get(TOOLS_HEADER)
    return frozenset(t for t in header.split(",") if t) if header is not None else None
