"""What every request through the gateway goes through: the upstreams' tool catalog and links, the caller
policy, the rate limiter, audit and metrics (``limiter`` and ``audit`` None switch those off)."""

from __future__ import annotations

from dataclasses import dataclass, field

import mcp.types as types

from bagmcp_gateway.access.policy import ToolPolicy
from bagmcp_gateway.access.ratelimit import RateLimiter
from bagmcp_gateway.mcp_front.audit import AuditLog
from bagmcp_gateway.mcp_front.metrics import GatewayMetrics
from bagmcp_gateway.mcp_front.wire_answers import DEFAULT_MAX_CHARS
from bagmcp_gateway.upstreams.connections import Connections
from bagmcp_gateway.upstreams.tool_catalog import ToolCatalog


@dataclass
class Gateway:
    tool_catalog: ToolCatalog
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
            await self.tool_catalog.refresh_all()
            self.tool_catalog.check_startup()
            self.listed = all(state.up for state in self.tool_catalog.states.values())
        return self.tool_catalog.tools
