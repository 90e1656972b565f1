"""What every request through the gateway goes through: the upstream catalog and links, the caller
policy, the rate limiter, audit and metrics (``limiter`` and ``audit`` None switch those off)."""

from __future__ import annotations

from dataclasses import dataclass, field

import mcp.types as types
from mcp.server.auth.provider import AccessToken

from bagmcp_gateway.access.policy import ToolPolicy
from bagmcp_gateway.access.ratelimit import RateLimiter
from bagmcp_gateway.mcp_front.audit import AuditLog
from bagmcp_gateway.mcp_front.metrics import GatewayMetrics
from bagmcp_gateway.mcp_front.wire_answers import DEFAULT_MAX_CHARS
from bagmcp_gateway.upstreams.connections import Connections
from bagmcp_gateway.upstreams.tool_catalog import ToolCatalog
from bagmcp_kit.identity import LOCAL_CALLER


@dataclass
class Gateway:
    catalog: ToolCatalog
    connections: Connections
    policy: ToolPolicy = field(default_factory=ToolPolicy)
    limiter: RateLimiter | None = None
    audit: AuditLog | None = None
    metrics: GatewayMetrics = field(default_factory=GatewayMetrics)
    max_answer_chars: int = DEFAULT_MAX_CHARS
    audit_arguments: bool = False
    listed: bool = False

    async def tools(self) -> list[types.Tool]:
        if not self.listed:  # in-process use (stdio, tests) lists on need until every upstream answered once
            await self.catalog.refresh_all()
            self.catalog.check_startup()
            self.listed = all(state.up for state in self.catalog.states.values())
        return self.catalog.tools


def who(caller: AccessToken | None) -> str:
    """The caller's name as audit records show it (the token's name, a JWT's subject)."""
    return caller.client_id if caller is not None else LOCAL_CALLER


def owner_of(caller: AccessToken | None) -> str:
    """Who owns the caller's jobs and rate-limit bucket, namespaced by kind (``token:alice``,
    ``static:<name>``, ``jwt:<issuer>:<sub>``; ``local`` without a token), so two kinds of identity that
    share a name never share jobs."""
    if caller is None:
        return LOCAL_CALLER
    owner = (caller.claims or {}).get("owner")
    return str(owner) if owner else f"token:{caller.client_id}"
