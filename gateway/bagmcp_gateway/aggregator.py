"""The gateway's MCP server: one tool list from all upstreams, calls routed to their owner.

Built on the low-level SDK server so upstream input and output schemas pass through unchanged.
A failing upstream drops out of tools/list (and its calls answer with an error) without
affecting the others.
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from contextlib import AbstractAsyncContextManager
from dataclasses import dataclass, field
from typing import Any

import anyio
import mcp.types as types
from mcp import Client, MCPError
from mcp.server import Server, ServerRequestContext
from mcp.server.auth.middleware.auth_context import get_access_token

from bagmcp_gateway.connections import Connections
from bagmcp_gateway.upstreams import GatewayConfigError, Upstream

log = logging.getLogger(__name__)
# Who called, for upstreams that keep per-caller state (jobs). Set here, never taken from the client.
OWNER_META_KEY = "bagmcp/owner"


@dataclass
class Routing:
    """Exposed tool name -> (upstream, original name), refreshed on every tools/list."""

    routes: dict[str, tuple[Upstream, str]] = field(default_factory=dict)
    down: dict[str, str] = field(default_factory=dict)


ClientOf = Callable[[Upstream], AbstractAsyncContextManager[Client]]


def _one_off(upstream: Upstream) -> AbstractAsyncContextManager[Client]:
    return upstream.client()


async def _list_one(upstream: Upstream, client_of: ClientOf) -> list[types.Tool]:
    with anyio.fail_after(upstream.timeout_s):
        async with client_of(upstream) as client:
            result = await client.list_tools()
    return list(result.tools)


async def collect_tools(
    upstreams: list[Upstream], routing: Routing, client_of: ClientOf = _one_off
) -> list[types.Tool]:
    """List every upstream concurrently; a failed upstream's tools are left out."""
    found: dict[str, list[types.Tool]] = {}

    async def one(upstream: Upstream) -> None:
        try:
            found[upstream.name] = await _list_one(upstream, client_of)
            routing.down.pop(upstream.name, None)
        except Exception as err:  # any transport failure means "down"; the others go on
            routing.down[upstream.name] = f"{type(err).__name__}: {err}"
            log.warning("upstream %s is unavailable: %s", upstream.name, err)

    async with anyio.create_task_group() as group:
        for upstream in upstreams:
            group.start_soon(one, upstream)
    tools: list[types.Tool] = []
    routes: dict[str, tuple[Upstream, str]] = {}
    for upstream in upstreams:
        for tool in found.get(upstream.name, []):
            name = upstream.exposed(tool.name)
            if name in routes:
                raise GatewayConfigError(
                    f"tool {name!r} is published by {routes[name][0].name} and {upstream.name}; "
                    "give one of them a prefix"
                )
            routes[name] = (upstream, tool.name)
            tools.append(tool.model_copy(update={"name": name}))
    routing.routes = routes
    return tools


def _error(text: str) -> types.CallToolResult:
    return types.CallToolResult(content=[types.TextContent(type="text", text=text)], is_error=True)


def build_gateway_server(
    upstreams: list[Upstream], *, name: str = "bagmcp", connections: Connections | None = None
) -> Server[Any]:
    """The aggregated MCP server over ``upstreams``; with ``connections`` (running), calls reuse
    long-lived upstream clients instead of opening one per call."""
    routing = Routing()
    client_of: ClientOf = connections.client if connections is not None else _one_off

    async def on_list_tools(
        ctx: ServerRequestContext[Any], params: types.PaginatedRequestParams | None
    ) -> types.ListToolsResult:
        try:
            return types.ListToolsResult(tools=await collect_tools(upstreams, routing, client_of))
        except GatewayConfigError as err:
            log.error("gateway configuration error: %s", err)
            raise MCPError(types.INTERNAL_ERROR, f"gateway configuration error: {err}") from err

    async def on_call_tool(ctx: ServerRequestContext[Any], params: types.CallToolRequestParams) -> types.CallToolResult:
        if params.name not in routing.routes:
            try:
                await collect_tools(upstreams, routing, client_of)
            except GatewayConfigError as err:
                return _error(f"gateway configuration error: {err}")
        route = routing.routes.get(params.name)
        if route is None:
            down = ", ".join(routing.down) or "none"
            return _error(f"Unknown tool: {params.name} (upstreams currently unavailable: {down})")
        upstream, original = route

        async def relay(progress: float, total: float | None, message: str | None) -> None:
            await ctx.session.report_progress(progress, total, message)

        token = get_access_token()
        meta = {OWNER_META_KEY: token.client_id if token is not None else "local"}
        try:
            async with client_of(upstream) as client:
                return await client.call_tool(original, params.arguments or {}, progress_callback=relay, meta=meta)  # type: ignore[arg-type]
        except Exception as err:  # transport failure: the tool is there but its service is not
            log.warning("call of %s on %s failed: %s", original, upstream.name, err)
            return _error(
                f"the {upstream.name} service is unavailable right now ({type(err).__name__}); try again shortly"
            )

    return Server(name, on_list_tools=on_list_tools, on_call_tool=on_call_tool)
