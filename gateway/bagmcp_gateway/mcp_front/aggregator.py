"""The gateway's MCP server: one tool list from every upstream (as the caller may see it), calls checked
again and routed (calls.py), the upstreams' resources listed and read (reads.py), and one instructions
text (the upstreams' own, each sentence once, or the configured one).

Built on the low-level SDK server so upstream schemas and answers pass through unchanged. A caller on the
2026-07-28 protocol gets a tool answer or a read result as the upstream sent it (in its wire form, stamped
with the gateway's identity): parsing it into SDK models and checking them again before dumping them would
be most of the gateway's own time per call, and the caller's client validates the answer anyway. Callers
on older protocol versions go through the SDK's handlers, which shape the answer for their version.
"""

from __future__ import annotations

import contextlib
from collections.abc import Callable, Mapping
from typing import Any

import mcp.types as types
from mcp import MCPError
from mcp.server import Server, ServerRequestContext
from mcp.server.apps import EXTENSION_ID as APPS_EXTENSION
from mcp.server.apps import client_supports_apps
from mcp.server.auth.middleware.auth_context import get_access_token
from mcp.server.context import CallNext, HandlerResult
from mcp.server.subscriptions import InMemorySubscriptionBus, ListenHandler, SubscriptionBus
from mcp_types.version import MODERN_PROTOCOL_VERSIONS

from bagmcp_gateway.mcp_front.calls import call_tool
from bagmcp_gateway.mcp_front.gateway import Gateway as Gateway  # re-exported: app.py builds one
from bagmcp_gateway.mcp_front.reads import list_resources, list_templates, read_resource
from bagmcp_gateway.upstreams.connections import Connections
from bagmcp_gateway.upstreams.relay import WireResult
from bagmcp_gateway.upstreams.tool_catalog import ToolCatalog
from bagmcp_gateway.upstreams.upstream import GatewayConfigError, Upstream
from bagmcp_kit.web.viewers import without_viewer


def _instructions_middleware(gateway: Gateway, configured: str | None) -> Any:
    """Answer initialize and server/discover with the instructions as they are now (upstreams connect later
    than the server is built; an in-process gateway lists them here, on its first request)."""

    async def with_instructions(ctx: ServerRequestContext[Any], call_next: CallNext) -> HandlerResult:
        if ctx.method not in ("initialize", "server/discover"):
            return await call_next(ctx)
        with contextlib.suppress(GatewayConfigError):  # tools/list reports it
            await gateway.tools()
        result = await call_next(ctx)
        text = configured or gateway.tool_catalog.instructions
        if isinstance(result, dict) and text:
            result["instructions"] = text
        return result

    return with_instructions


def _relayed(result: WireResult, stamp: dict[str, Any] | None) -> WireResult:
    """An upstream's answer as this server's: without the upstream's identity stamp, and for a 2026-07-28
    caller (``stamp`` given) complete and stamped as coming from here."""
    meta = result.get("_meta")
    kept = {k: v for k, v in meta.items() if k != types.SERVER_INFO_META_KEY} if isinstance(meta, dict) else {}
    if stamp is None:
        return {**result, "_meta": kept} if kept else {k: v for k, v in result.items() if k != "_meta"}
    return {
        **result,
        "resultType": result.get("resultType", "complete"),
        "_meta": {**kept, types.SERVER_INFO_META_KEY: stamp},
    }


async def _relay(gateway: Gateway, ctx: ServerRequestContext[Any], params: Mapping[str, Any]) -> WireResult | None:
    """The answer of a tools/call or resources/read relayed in its wire form; None for anything else (or
    params the SDK should reject with its own error)."""
    if ctx.method == "tools/call":
        name, arguments = params.get("name"), params.get("arguments")
        if isinstance(name, str) and isinstance(arguments, dict | None):
            return await call_tool(gateway, ctx, name, arguments or {})
    if ctx.method == "resources/read" and isinstance(uri := params.get("uri"), str):
        return await read_resource(gateway, uri)
    return None


def _relay_middleware(gateway: Gateway, stamp: Callable[[], dict[str, Any]]) -> Any:
    """Answer a 2026-07-28 caller's tools/call and resources/read with the upstream's result as it came."""

    async def relayed(ctx: ServerRequestContext[Any], call_next: CallNext) -> HandlerResult:
        if ctx.protocol_version in MODERN_PROTOCOL_VERSIONS:
            answer = await _relay(gateway, ctx, ctx.params or {})
            if answer is not None:
                return _relayed(answer, stamp())
        return await call_next(ctx)

    return relayed


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
        shown = gateway.policy.shown(tools, get_access_token())
        if not client_supports_apps(ctx):  # a client without MCP Apps gets the listing it always had
            shown = [without_viewer(t) for t in shown]
        return types.ListToolsResult(tools=shown)

    async def on_call_tool(ctx: ServerRequestContext[Any], params: types.CallToolRequestParams) -> WireResult:
        """Callers of older protocol versions (the SDK shapes the answer for theirs)."""
        return _relayed(await call_tool(gateway, ctx, params.name, params.arguments or {}), None)

    async def on_list_resources(
        ctx: ServerRequestContext[Any], params: types.PaginatedRequestParams | None
    ) -> types.ListResourcesResult:
        return await list_resources(gateway)

    async def on_list_templates(
        ctx: ServerRequestContext[Any], params: types.PaginatedRequestParams | None
    ) -> types.ListResourceTemplatesResult:
        return await list_templates(gateway)

    async def on_read_resource(ctx: ServerRequestContext[Any], params: types.ReadResourceRequestParams) -> WireResult:
        return _relayed(await read_resource(gateway, params.uri), None)

    server = Server(
        name,
        on_list_tools=on_list_tools,
        on_call_tool=on_call_tool,  # type: ignore[arg-type]  # a wire-form dict: the SDK validates it
        on_list_resources=on_list_resources,
        on_list_resource_templates=on_list_templates,
        on_read_resource=on_read_resource,  # type: ignore[arg-type]
        on_subscriptions_listen=ListenHandler(bus),
        get_tool_input_schema=gateway.tool_catalog.header_schema,  # else the SDK lists every tool per call
    )
    server.extensions[APPS_EXTENSION] = {}  # MCP Apps: viewers of the upstreams' tools are relayed (reads.py)
    server.middleware.append(_instructions_middleware(gateway, instructions))
    server.middleware.append(_relay_middleware(gateway, lambda: server.server_info_stamp))
    return server


def build_gateway_server(
    upstreams: list[Upstream], *, connections: Connections | None = None, name: str = "bagmcp"
) -> Server[Any]:
    """An aggregating server for in-process use (stdio, tests): no auth, limits or background refresh;
    ``connections`` (when its ``run`` is going) keeps long-lived upstream clients."""
    bus = InMemorySubscriptionBus()
    links = connections or Connections(upstreams)
    return gateway_server(Gateway(ToolCatalog(upstreams, links, bus), links), bus, name=name)
