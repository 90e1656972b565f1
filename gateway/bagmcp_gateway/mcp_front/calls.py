"""One tool call through the gateway: checked again (the tool is there, the caller may call it), rate
limited, sent to its upstream with progress relayed, capped, audited and counted. The answer stays in its
wire form from the upstream to the caller (wire_answers.py)."""

from __future__ import annotations

import json
import logging
import time
from collections.abc import Awaitable, Callable
from typing import Any, cast

import anyio
from mcp.server import ServerRequestContext
from mcp.server.apps import client_supports_apps
from mcp.server.auth.middleware.auth_context import get_access_token
from mcp.server.auth.provider import AccessToken
from mcp.shared.inbound import mcp_param_headers
from mcp.types import RequestParamsMeta

from bagmcp_gateway.access.identities import owner_of, who
from bagmcp_gateway.access.ratelimit import retry_after_s
from bagmcp_gateway.mcp_front.audit import AuditRecord
from bagmcp_gateway.mcp_front.gateway import Gateway
from bagmcp_gateway.mcp_front.wire_answers import cap_answer, error_result, is_error, text_characters
from bagmcp_gateway.upstreams.connections import sole_error
from bagmcp_gateway.upstreams.relay import WireResult
from bagmcp_gateway.upstreams.resource_routes import with_exposed_links
from bagmcp_gateway.upstreams.tool_catalog import ToolRoute
from bagmcp_gateway.upstreams.upstream import Upstream
from bagmcp_kit.fetch_meta import FETCHED_META_KEY
from bagmcp_kit.identity import owner_meta
from bagmcp_kit.web.viewers import asking_for_views, without_view_data
from bagmcp_shared.errors import BagmcpError

log = logging.getLogger(__name__)


async def _forward(
    gateway: Gateway,
    ctx: ServerRequestContext[Any],
    route: ToolRoute,
    arguments: dict[str, Any],
    caller: AccessToken | None,
) -> WireResult:
    async def relay_progress(progress: float, total: float | None, message: str | None) -> None:
        await ctx.session.report_progress(progress, total, message)

    meta = owner_meta(owner_of(caller), tools=gateway.policy.callable_names(gateway.tool_catalog.tools, caller))
    if client_supports_apps(ctx):  # the service adds the data to draw only for callers that draw it
        meta = cast(RequestParamsMeta, asking_for_views(dict(meta)))

    async def send() -> WireResult:
        async with gateway.connections.link(route.upstream) as link:
            if link.relay is not None:
                params = {"name": route.original, "arguments": arguments}
                headers = mcp_param_headers(route.param_headers, arguments) if route.param_headers else None
                return await link.relay.request(
                    "tools/call", params, meta=meta, headers=headers, progress=relay_progress
                )
            result = await link.client.call_tool(route.original, arguments, progress_callback=relay_progress, meta=meta)
            return result.model_dump(by_alias=True, mode="json", exclude_none=True)

    with anyio.fail_after(route.upstream.call_timeout_s):
        return await _unless_it_goes_down(gateway, route.upstream, send)


class UpstreamWentDownError(BagmcpError):
    """The upstream stopped answering the gateway's listing while a call to it was in flight."""


async def _unless_it_goes_down(
    gateway: Gateway, upstream: Upstream, send: Callable[[], Awaitable[WireResult]]
) -> WireResult:
    """``send()``, or UpstreamWentDownError as soon as the catalog finds ``upstream`` down meanwhile (a service
    that was stopped, frozen or cut off answers nothing: the call waited for its limit, 600 s by default; now
    at most the catalog's poll plus its listing timeout, 15 s by default)."""
    answered: list[WireResult] = []
    down: list[str] = []

    async def call() -> None:
        answered.append(await send())
        group.cancel_scope.cancel()

    async def watch() -> None:
        down.append(await gateway.tool_catalog.went_down(upstream))
        group.cancel_scope.cancel()

    try:
        async with anyio.create_task_group() as group:
            group.start_soon(call)
            group.start_soon(watch)
    except ExceptionGroup as errors:  # the call's own failure, as it was raised
        raise sole_error(errors) from None
    if answered:
        return answered[0]
    raise UpstreamWentDownError(down[0] if down else "it stopped answering")


async def _route_of(gateway: Gateway, name: str) -> ToolRoute | None:
    """Where ``name`` goes; for a tool of a service the catalog has down, after one more look at that service
    (it may just have come back)."""
    catalog = gateway.tool_catalog
    route = catalog.routes.get(name)
    gone = catalog.known.get(name) if route is None else None
    return catalog.routes.get(name) if gone is not None and await catalog.recheck(gone) else route


def _missing(gateway: Gateway, name: str, record: AuditRecord) -> WireResult:
    gone = gateway.tool_catalog.known.get(name)
    record.outcome, record.upstream = ("unavailable", gone.name) if gone else ("unknown_tool", None)
    if gone is not None:
        return error_result(
            f"the {gone.name} service is unavailable right now, so {name} cannot run; try again shortly"
        )
    down = ", ".join(n for n, state in gateway.tool_catalog.published.items() if not state.up) or "none"
    return error_result(f"Unknown tool: {name} (services unavailable right now: {down})")


async def _checked_call(
    gateway: Gateway,
    ctx: ServerRequestContext[Any],
    name: str,
    arguments: dict[str, Any],
    caller: AccessToken | None,
    record: AuditRecord,
) -> WireResult:
    await gateway.tools()
    route = await _route_of(gateway, name)
    if route is None:
        return _missing(gateway, name, record)
    upstream = route.upstream
    record.upstream = upstream.name
    if not gateway.policy.allows(route.tool, caller):
        record.outcome = "denied"
        return error_result(gateway.policy.refusal(route.tool, caller))
    if gateway.limiter is not None and (wait := await gateway.limiter.take(owner_of(caller))):
        record.outcome = "rate_limited"
        after = retry_after_s(wait)
        return error_result(f"rate limit reached for this token; retry after {after} s", retryAfterSeconds=after)
    try:
        result = await _forward(gateway, ctx, route, arguments, caller)
    except UpstreamWentDownError as err:
        log.warning("call of %s on %s ended: the service stopped answering (%s)", route.original, upstream.name, err)
        record.outcome = "unavailable"
        return error_result(
            f"the {upstream.name} service stopped answering while it worked on {name}, so the call was ended; "
            "try again once it is back (see /readyz)"
        )
    except TimeoutError:
        log.warning("call of %s on %s timed out after %s s", route.original, upstream.name, upstream.call_timeout_s)
        gateway.tool_catalog.failed(upstream)
        record.outcome = "unavailable"
        return error_result(
            f"the {upstream.name} service did not answer {name} within {upstream.call_timeout_s:g} s (its time "
            "limit); ask for less work, or try again later"
        )
    except Exception as err:  # transport failure (or a protocol error): the tool is there but its service is not
        log.warning("call of %s on %s failed: %s", route.original, upstream.name, err)
        gateway.tool_catalog.failed(upstream)
        record.outcome = "unavailable"
        return error_result(
            f"the {upstream.name} service is unavailable right now ({type(err).__name__}); try again shortly"
        )
    record.outcome = "error" if is_error(result) else "ok"
    if not client_supports_apps(ctx):  # the data of an MCP Apps view is only for clients that draw it
        result = without_view_data(result)
    return cap_answer(with_exposed_links(result, upstream), max_chars=gateway.max_answer_chars)


async def call_tool(
    gateway: Gateway, ctx: ServerRequestContext[Any], name: str, arguments: dict[str, Any]
) -> WireResult:
    caller = get_access_token()
    began = time.perf_counter()
    record = AuditRecord(token=who(caller), tool=name, upstream=None)
    if gateway.audit is not None:
        record.request_bytes = len(json.dumps(arguments, default=str))
        record.arguments = dict(arguments) if gateway.audit_arguments else None
    result = await _checked_call(gateway, ctx, name, arguments, caller, record)
    seconds = time.perf_counter() - began
    gateway.metrics.record(name, record.upstream or "-", record.outcome, seconds)
    if gateway.audit is not None:
        record.duration_ms = round(seconds * 1000, 3)
        record.response_bytes = text_characters(result)
        record.fetched_bytes = (result.get("_meta") or {}).get(FETCHED_META_KEY)
        gateway.audit.write(record)
    return result
