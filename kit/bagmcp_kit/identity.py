"""Who called a tool: the gateway (which alone holds the service credential) names the caller in
the request metadata; a tool called in process without a gateway belongs to "local"."""

from __future__ import annotations

from mcp.server.mcpserver import Context

OWNER_META_KEY = "bagmcp/owner"
LOCAL_CALLER = "local"


def caller(ctx: Context) -> str:
    meta = ctx.request_context.meta or {}
    owner = meta.get(OWNER_META_KEY)
    return str(owner) if owner else LOCAL_CALLER
