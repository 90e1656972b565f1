"""``create_app``: the gateway: aggregated MCP at /mcp (tokens, tool policy, rate limits, audit, metrics),
REST under /api/v1 (proxied or embedded, and the admin routes for tokens), /healthz, /readyz, /metrics.

Only the composition lives here: the access parts come from access/assembly.py, the MCP endpoint from
mcp_front/endpoint.py, what runs while serving from lifespan.py, the health routes from rest_front/health.py."""

from __future__ import annotations

from collections.abc import Callable, Sequence

from fastapi import APIRouter, FastAPI
from mcp.server.auth.provider import AccessToken
from mcp.server.subscriptions import InMemorySubscriptionBus

from bagmcp_gateway.access.assembly import rate_limiter, token_store, token_verifier
from bagmcp_gateway.access.auth import rest_auth
from bagmcp_gateway.access.tokens.admin import TokenNotFoundError, build_admin_router
from bagmcp_gateway.access.tokens.store import TokenStore
from bagmcp_gateway.access.tokens.verifier import GatewayVerifier
from bagmcp_gateway.access.upload_limits import UploadGuard, UploadStalledError
from bagmcp_gateway.lifespan import gateway_lifespan
from bagmcp_gateway.mcp_front.aggregator import gateway_server
from bagmcp_gateway.mcp_front.audit import AuditLog
from bagmcp_gateway.mcp_front.endpoint import mcp_endpoint
from bagmcp_gateway.mcp_front.gateway import Gateway
from bagmcp_gateway.mcp_front.metrics import GatewayMetrics
from bagmcp_gateway.rest_front.console import build_session_router, install_console
from bagmcp_gateway.rest_front.health import metrics_router, readiness_router
from bagmcp_gateway.rest_front.lab_routes import install_lab_page
from bagmcp_gateway.settings import GatewaySettings
from bagmcp_gateway.upstreams.change_events import RedisSubscriptionBus, channel_for
from bagmcp_gateway.upstreams.connections import Connections
from bagmcp_gateway.upstreams.tool_catalog import ToolCatalog
from bagmcp_gateway.upstreams.upstream import Upstream
from bagmcp_kit.error_shape import UniformErrors
from bagmcp_kit.http_errors import StatusTable
from bagmcp_kit.service_app import new_app
from bagmcp_shared.redis_connection import redis_client

ADMIN_STATUSES: StatusTable = [(TokenNotFoundError, 404, "token_not_found")]
UPLOAD_STATUSES: StatusTable = [(UploadStalledError, 408, "upload_stalled")]


def create_app(
    settings: GatewaySettings,
    *,
    upstreams: list[Upstream],
    rest: Sequence[APIRouter],
    statuses: StatusTable = (),
    on_shutdown: Callable[[], None] | None = None,
) -> FastAPI:
    """The gateway app over ``upstreams``. ``rest`` serves /api/v1: the proxy in team mode, the
    services' own routes when embedded (``statuses`` then maps their errors)."""
    store = token_store(settings.redis_url, settings.tokens_file)
    verifier = None
    if settings.authenticated:
        verifier = token_verifier(store, static_hashes=settings.token_hashes, jwt=settings.jwt)
    redis_url = settings.redis_url
    shared_bus = RedisSubscriptionBus(redis_url, channel=channel_for(upstreams)) if redis_url is not None else None
    bus = shared_bus or InMemorySubscriptionBus()
    connections = Connections(upstreams)
    gateway = Gateway(
        ToolCatalog(upstreams, connections, bus, poll_s=settings.upstream_poll_s),
        connections,
        policy=settings.policy,
        limiter=rate_limiter(settings.rate_limit, redis_url),
        audit=AuditLog() if settings.audit else None,
        metrics=GatewayMetrics(),
        max_answer_chars=settings.max_answer_chars,
        audit_arguments=settings.audit_arguments,
    )
    server = gateway_server(gateway, bus, instructions=settings.instructions)

    async def tools_for(caller: AccessToken | None) -> list[str] | None:
        return gateway.policy.callable_names(await gateway.tools(), caller)

    app = new_app(
        title="bagmcp gateway",
        lifespan=gateway_lifespan(gateway, server, shared_bus=shared_bus, on_shutdown=on_shutdown),
        routers=_routers(settings, gateway, store, verifier, rest),
        guard=rest_auth(verifier, tools_for),
        allowed_hosts=settings.http.allowed_hosts,
        statuses=[*ADMIN_STATUSES, *UPLOAD_STATUSES, *statuses],
    )
    shared_redis = redis_client(redis_url) if redis_url is not None else None
    app.include_router(readiness_router(gateway.tool_catalog, gateway.metrics, shared_redis))
    app.add_middleware(UploadGuard, limits=settings.uploads)
    install_console(app, token_required=verifier is not None)
    install_lab_page(app)
    app.mount("/", UniformErrors(mcp_endpoint(server, verifier, public_url=settings.public_url)))
    return app


def _routers(
    settings: GatewaySettings,
    gateway: Gateway,
    store: TokenStore | None,
    verifier: GatewayVerifier | None,
    rest: Sequence[APIRouter],
) -> list[APIRouter]:
    """The guarded routes: token admin and the session first (team mode forwards every other /api/v1 path to
    a service), then ``rest``, then /metrics."""
    routers = [build_session_router(verifier, tokens_managed=store is not None and verifier is not None), *rest]
    if store is not None and verifier is not None:
        routers.insert(0, build_admin_router(store, profiles=list(settings.policy.profiles), forget=verifier.forget))
    return [*routers, metrics_router(gateway.metrics)]
