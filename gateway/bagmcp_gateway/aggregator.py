"""The gateway's MCP server: one tool list from every upstream (as the caller may see it), calls checked
again, rate limited, routed to their upstream with progress relayed, capped, audited and counted, and
one instructions text (the upstreams' own, each sentence once, or the configured one).

Built on the low-level SDK server so upstream input and output schemas pass through unchanged.
"""

from __future__ import annotations

import contextlib
import json
import logging
import time
from dataclasses import dataclass, field
from typing import Any

import anyio
import mcp.types as types
from mcp import MCPError
from mcp.server import Server, ServerRequestContext
from mcp.server.auth.middleware.auth_context import get_access_token
from mcp.server.auth.provider import AccessToken
from mcp.server.context import CallNext, HandlerResult
from mcp.server.subscriptions import InMemorySubscriptionBus, ListenHandler, SubscriptionBus

from bagmcp_gateway.answers import DEFAULT_MAX_CHARS, cap_answer, error_result
from bagmcp_gateway.audit import AuditLog, AuditRecord
from bagmcp_gateway.catalog import ToolCatalog
from bagmcp_gateway.connections import Connections
from bagmcp_gateway.metrics import GatewayMetrics
from bagmcp_gateway.policy import ToolPolicy
from bagmcp_gateway.ratelimit import RateLimiter, retry_after_s
from bagmcp_gateway.upstreams import GatewayConfigError, Upstream
from bagmcp_kit.identity import LOCAL_CALLER, OWNER_META_KEY

log = logging.getLogger(__name__)


@dataclass
class Gateway:
    """Everything a call goes through; ``limiter`` and ``audit`` None switch those off."""

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


def _who(caller: AccessToken | None) -> str:
    return caller.client_id if caller is not None else LOCAL_CALLER


async def _forward(
    gateway: Gateway,
    ctx: ServerRequestContext[Any],
    upstream: Upstream,
    original: str,
    arguments: dict[str, Any],
    who: str,
) -> types.CallToolResult:
    async def relay(progress: float, total: float | None, message: str | None) -> None:
        await ctx.session.report_progress(progress, total, message)

    with anyio.fail_after(upstream.call_timeout_s):
        async with gateway.connections.client(upstream) as client:
            return await client.call_tool(original, arguments, progress_callback=relay, meta={OWNER_META_KEY: who})  # type: ignore[arg-type]


async def call_tool(
    gateway: Gateway, ctx: ServerRequestContext[Any], params: types.CallToolRequestParams
) -> types.CallToolResult:
    caller = get_access_token()
    who = _who(caller)
    arguments = params.arguments or {}
    began = time.perf_counter()
    record = AuditRecord(
        token=who, tool=params.name, upstream=None, request_bytes=len(json.dumps(arguments, default=str))
    )
    if gateway.audit_arguments:
        record.arguments = dict(arguments)
    result = await _checked_call(gateway, ctx, params.name, arguments, caller, record)
    record.duration_ms = round((time.perf_counter() - began) * 1000, 3)
    record.response_bytes = sum(len(c.text) for c in result.content if isinstance(c, types.TextContent))
    gateway.metrics.record(params.name, record.upstream or "-", record.outcome, time.perf_counter() - began)
    if gateway.audit is not None:
        gateway.audit.write(record)
    return result


async def _checked_call(
    gateway: Gateway,
    ctx: ServerRequestContext[Any],
    name: str,
    arguments: dict[str, Any],
    caller: AccessToken | None,
    record: AuditRecord,
) -> types.CallToolResult:
    await gateway.tools()
    tool, route = gateway.catalog.tool(name), gateway.catalog.routes.get(name)
    if tool is None or route is None:
        gone = gateway.catalog.known.get(name)
        record.outcome, record.upstream = ("unavailable", gone.name) if gone else ("unknown_tool", None)
        if gone is not None:
            return error_result(
                f"the {gone.name} service is unavailable right now, so {name} cannot run; try again shortly"
            )
        down = ", ".join(n for n, state in gateway.catalog.states.items() if not state.up) or "none"
        return error_result(f"Unknown tool: {name} (services unavailable right now: {down})")
    upstream, original = route
    record.upstream = upstream.name
    if not gateway.policy.allows(tool, caller):
        record.outcome = "denied"
        return error_result(f"{name} is not enabled for this token (its profile, allow/deny lists or scopes)")
    if gateway.limiter is not None and (wait := await anyio.to_thread.run_sync(gateway.limiter.take, _who(caller))):
        record.outcome = "rate_limited"
        after = retry_after_s(wait)
        return error_result(f"rate limit reached for this token; retry after {after} s", retryAfterSeconds=after)
    try:
        result = await _forward(gateway, ctx, upstream, original, arguments, _who(caller))
    except TimeoutError:
        log.warning("call of %s on %s timed out after %s s", original, upstream.name, upstream.call_timeout_s)
        gateway.catalog.failed(upstream)
        record.outcome = "unavailable"
        return error_result(
            f"the {upstream.name} service did not answer {name} within {upstream.call_timeout_s:g} s (its time "
            "limit); ask for less work, or try again later"
        )
    except Exception as err:  # transport failure: the tool is there but its service is not
        log.warning("call of %s on %s failed: %s", original, upstream.name, err)
        gateway.catalog.failed(upstream)
        record.outcome = "unavailable"
        return error_result(
            f"the {upstream.name} service is unavailable right now ({type(err).__name__}); try again shortly"
        )
    record.outcome = "error" if result.is_error else "ok"
    return cap_answer(result, max_chars=gateway.max_answer_chars)


def _instructions_middleware(gateway: Gateway, configured: str | None) -> Any:
    """Answer initialize and server/discover with the instructions as they are now (upstreams connect later
    than the server is built; an in-process gateway lists them here, on its first request)."""

    async def with_instructions(ctx: ServerRequestContext[Any], call_next: CallNext) -> HandlerResult:
        if ctx.method not in ("initialize", "server/discover"):
            return await call_next(ctx)
        with contextlib.suppress(GatewayConfigError):  # tools/list reports it
            await gateway.tools()
        result = await call_next(ctx)
        text = configured or gateway.catalog.instructions
        if isinstance(result, dict) and text:
            result["instructions"] = text
        return result

    return with_instructions


def gateway_server(
    gateway: Gateway, bus: SubscriptionBus, *, name: str = "bagmcp", instructions: str | None = None
) -> Server[Any]:
    """``instructions`` replaces the upstreams' own (None: theirs, each sentence once)."""

    async def on_list_tools(
        ctx: ServerRequestContext[Any], params: types.PaginatedRequestParams | None
    ) -> types.ListToolsResult:
        try:
            tools = await gateway.tools()
        except GatewayConfigError as err:
            raise MCPError(types.INTERNAL_ERROR, f"gateway configuration error: {err}") from err
        return types.ListToolsResult(tools=gateway.policy.shown(tools, get_access_token()))

    async def on_call_tool(ctx: ServerRequestContext[Any], params: types.CallToolRequestParams) -> types.CallToolResult:
        return await call_tool(gateway, ctx, params)

    def input_schema(tool_name: str) -> dict[str, Any] | None:
        """For the SDK's check of a call's Mcp-Param headers: without it, the SDK runs (and serializes) a
        whole tools/list on every tools/call to find this one schema."""
        tool = gateway.catalog.tool(tool_name)
        return tool.input_schema if tool is not None else None

    server = Server(
        name,
        on_list_tools=on_list_tools,
        on_call_tool=on_call_tool,
        on_subscriptions_listen=ListenHandler(bus),
        get_tool_input_schema=input_schema,
    )
    server.middleware.append(_instructions_middleware(gateway, instructions))
    return server


def build_gateway_server(
    upstreams: list[Upstream], *, connections: Connections | None = None, name: str = "bagmcp"
) -> Server[Any]:
    """An aggregating server for in-process use (stdio, tests): no auth, limits or background refresh;
    ``connections`` (when its ``run`` is going) keeps long-lived upstream clients."""
    bus = InMemorySubscriptionBus()
    links = connections or Connections(upstreams)
    return gateway_server(Gateway(ToolCatalog(upstreams, links, bus), links), bus, name=name)
