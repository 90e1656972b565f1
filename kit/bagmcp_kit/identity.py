"""Who called a tool: the gateway (which alone holds the service credential) names the caller in
the request metadata; a tool called in process without a gateway belongs to "local"."""

from __future__ import annotations

from typing import cast

from mcp.server.mcpserver import Context
from mcp.types import RequestParamsMeta

OWNER_META_KEY = "bagmcp/owner"
LOCAL_CALLER = "local"


def caller(ctx: Context) -> str:
    meta = ctx.request_context.meta or {}
    owner = meta.get(OWNER_META_KEY)
    return str(owner) if owner else LOCAL_CALLER


def owner_meta(who: str) -> RequestParamsMeta:
    """The request metadata naming the caller, as the gateway sends it to a service."""
    return cast(RequestParamsMeta, {OWNER_META_KEY: who})
