"""MCP resources through the gateway: ``resources/list`` and ``resources/templates/list`` from the upstreams
(as resource_routes.py exposes them), filtered as the policy says, and ``resources/read`` sent to the
upstream whose resource or template matches. A read needs the ``read`` scope and an upstream whose tools
the caller may use; its answer is relayed in its wire form, like a tool's."""

from __future__ import annotations

import time

import anyio
import mcp.types as types
from mcp import MCPError
from mcp.server.auth.middleware.auth_context import get_access_token
from mcp.server.auth.provider import AccessToken

from bagmcp_gateway.access.identities import owner_of, who
from bagmcp_gateway.access.ratelimit import retry_after_s
from bagmcp_gateway.mcp_front.audit import AuditRecord
from bagmcp_gateway.mcp_front.gateway import Gateway
from bagmcp_gateway.upstreams.relay import WireResult
from bagmcp_gateway.upstreams.resource_routes import with_exposed_contents
from bagmcp_gateway.upstreams.upstream import Upstream
from bagmcp_kit.identity import owner_meta

READ = "resources/read"
REQUEST_LIMITED = -32005  # implementation-defined JSON-RPC server error: this caller is over its rate limit


def _readable(gateway: Gateway, caller: AccessToken | None) -> set[str]:
    """The upstreams whose resources ``caller`` may list and read."""
    tool_catalog = gateway.tool_catalog
    return {u.name for u in tool_catalog.upstreams if gateway.policy.may_read(tool_catalog.tools_of(u), caller)}


async def list_resources(gateway: Gateway) -> types.ListResourcesResult:
    await gateway.tools()
    readable = _readable(gateway, get_access_token())
    return types.ListResourcesResult(
        resources=[r for u, r in gateway.tool_catalog.resources.resources if u.name in readable]
    )


async def list_templates(gateway: Gateway) -> types.ListResourceTemplatesResult:
    await gateway.tools()
    readable = _readable(gateway, get_access_token())
    templates = [t for u, t in gateway.tool_catalog.resources.templates if u.name in readable]
    return types.ListResourceTemplatesResult(resource_templates=templates)


async def _fetch(gateway: Gateway, upstream: Upstream, uri: str, caller: str) -> WireResult:
    meta = owner_meta(caller)
    with anyio.fail_after(upstream.call_timeout_s):
        async with gateway.connections.link(upstream) as link:
            if link.relay is not None:
                return await link.relay.request("resources/read", {"uri": uri}, meta=meta)
            result = await link.client.read_resource(uri, meta=meta)
            return result.model_dump(by_alias=True, mode="json", exclude_none=True)


def _refused(code: int, message: str, uri: str) -> MCPError:
    return MCPError(code, message, {"uri": uri})


async def _checked_read(gateway: Gateway, uri: str, caller: AccessToken | None, record: AuditRecord) -> WireResult:
    await gateway.tools()
    route = gateway.tool_catalog.resources.route(uri)
    if route is None:
        record.outcome = "unknown_resource"
        raise _refused(
            types.INVALID_PARAMS,
            f"no resource {uri!r} is served here; use a URI from a tool answer's resource link or from "
            "resources/list and resources/templates/list",
            uri,
        )
    upstream = route.upstream
    record.upstream = upstream.name
    if upstream.name not in _readable(gateway, caller):
        record.outcome = "denied"
        raise _refused(
            types.INVALID_REQUEST,
            f"this token may not read {uri!r}: reading the {upstream.name} service's resources needs the read "
            "scope and one of its tools enabled for the token",
            uri,
        )
    if gateway.limiter is not None and (wait := await gateway.limiter.take(owner_of(caller))):
        record.outcome = "rate_limited"
        raise _refused(REQUEST_LIMITED, f"rate limit reached for this token; retry after {retry_after_s(wait)} s", uri)
    try:
        result = await _fetch(gateway, upstream, route.uri, owner_of(caller))
    except MCPError:  # the service answered (an unknown id, say): its message tells the caller what to do
        record.outcome = "error"
        raise
    except Exception as err:  # transport failure or timeout
        gateway.tool_catalog.failed(upstream)
        record.outcome = "unavailable"
        message = f"the {upstream.name} service is unavailable right now ({type(err).__name__}); try again shortly"
        raise _refused(types.INTERNAL_ERROR, message, uri) from err
    return with_exposed_contents(result, upstream)


async def read_resource(gateway: Gateway, uri: str) -> WireResult:
    """The upstream's answer to reading ``uri``; MCPError saying what to do when it cannot be read. Audited
    and counted like a tool call (under the method's name)."""
    caller = get_access_token()
    record = AuditRecord(token=who(caller), tool=READ, upstream=None, request_bytes=len(uri))
    began = time.perf_counter()
    try:
        return await _checked_read(gateway, uri, caller, record)
    finally:
        seconds = time.perf_counter() - began
        gateway.metrics.record(READ, record.upstream or "-", record.outcome, seconds)
        if gateway.audit is not None:
            record.duration_ms = round(seconds * 1000, 3)
            gateway.audit.write(record)
