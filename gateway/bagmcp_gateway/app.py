"""``create_app``: the gateway: aggregated MCP at /mcp (tokens, tool policy, rate limits, audit, metrics),
REST under /api/v1 (proxied or embedded, and the admin routes for tokens), /healthz, /readyz, /metrics."""

from __future__ import annotations

import contextlib
from collections.abc import AsyncIterator, Callable, Sequence

import anyio
from fastapi import APIRouter, Depends, FastAPI
from fastapi.responses import JSONResponse, Response
from mcp.server.auth.provider import AccessToken
from mcp.server.auth.settings import AuthSettings
from mcp.server.subscriptions import InMemorySubscriptionBus
from pydantic import AnyHttpUrl

from bagmcp_gateway.aggregator import Gateway, gateway_server
from bagmcp_gateway.audit import AuditLog
from bagmcp_gateway.auth import rest_auth
from bagmcp_gateway.catalog import ToolCatalog
from bagmcp_gateway.connections import Connections
from bagmcp_gateway.console import build_session_router, install_console
from bagmcp_gateway.events import RedisSubscriptionBus, channel_for
from bagmcp_gateway.lab_routes import install_lab_page
from bagmcp_gateway.metrics import GatewayMetrics
from bagmcp_gateway.ratelimit import MemoryRateLimiter, RateLimiter, RedisRateLimiter
from bagmcp_gateway.readiness import down_dependencies
from bagmcp_gateway.settings import GatewaySettings
from bagmcp_gateway.tokens.admin import TokenNotFoundError, build_admin_router
from bagmcp_gateway.tokens.models import SCOPES, TokenRecord
from bagmcp_gateway.tokens.store import FileTokenStore, RedisTokenStore, TokenStore
from bagmcp_gateway.tokens.verifier import GatewayVerifier
from bagmcp_gateway.uploads import UploadGuard, UploadStalledError
from bagmcp_gateway.upstreams import Upstream
from bagmcp_kit.error_shape import UniformErrors
from bagmcp_kit.http_errors import StatusTable
from bagmcp_kit.runtime.resources import redis_client
from bagmcp_kit.service_app import HOST_CHECK_IN_MIDDLEWARE, new_app
from bagmcp_shared.redis_errors import answers

ADMIN_STATUSES: StatusTable = [(TokenNotFoundError, 404, "token_not_found")]
UPLOAD_STATUSES: StatusTable = [(UploadStalledError, 408, "upload_stalled")]


def _token_store(settings: GatewaySettings) -> TokenStore | None:
    if settings.redis_url is not None:
        return RedisTokenStore(redis_client(settings.redis_url))
    return FileTokenStore(settings.tokens_file) if settings.tokens_file is not None else None


def _limiter(settings: GatewaySettings) -> RateLimiter | None:
    if settings.rate_limit is None:
        return None
    if settings.redis_url is not None:
        return RedisRateLimiter(redis_client(settings.redis_url), settings.rate_limit)
    return MemoryRateLimiter(settings.rate_limit)


def _verifier(settings: GatewaySettings, store: TokenStore | None) -> GatewayVerifier | None:
    if not settings.authenticated:
        return None
    static = {h: TokenRecord(name=f"token-{h[:8]}", hash=h, scopes=list(SCOPES)) for h in settings.token_hashes}
    return GatewayVerifier(store, static=static, jwt_settings=settings.jwt)


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
    store = _token_store(settings)
    verifier = _verifier(settings, store)
    redis_url = settings.redis_url
    shared_bus = RedisSubscriptionBus(redis_url, channel=channel_for(upstreams)) if redis_url is not None else None
    bus = shared_bus or InMemorySubscriptionBus()
    connections = Connections(upstreams)
    catalog = ToolCatalog(upstreams, connections, bus, poll_s=settings.upstream_poll_s)
    gateway = Gateway(
        catalog,
        connections,
        policy=settings.policy,
        limiter=_limiter(settings),
        audit=AuditLog() if settings.audit else None,
        metrics=GatewayMetrics(),
        max_answer_chars=settings.max_answer_chars,
        audit_arguments=settings.audit_arguments,
    )
    server = gateway_server(gateway, bus, instructions=settings.instructions)
    auth = None
    if verifier is not None:
        auth = AuthSettings(
            issuer_url=AnyHttpUrl(settings.public_url),
            resource_server_url=AnyHttpUrl(f"{settings.public_url}/mcp"),
            required_scopes=["read"],
            validate_token_resource=False,
        )
    mcp_app = server.streamable_http_app(
        streamable_http_path="/mcp",
        stateless_http=True,
        json_response=False,
        transport_security=HOST_CHECK_IN_MIDDLEWARE,
        auth=auth,
        token_verifier=verifier,
    )

    @contextlib.asynccontextmanager
    async def lifespan(_app: FastAPI) -> AsyncIterator[None]:
        async with anyio.create_task_group() as group:
            if shared_bus is not None:
                await group.start(shared_bus.run)
            await group.start(connections.run)
            await catalog.refresh_all()
            catalog.check_startup()  # a tool name two upstreams publish stops the gateway here, naming both
            gateway.listed = True
            await group.start(catalog.run)
            async with server.session_manager.run():
                yield
            group.cancel_scope.cancel()
        if gateway.audit is not None:
            gateway.audit.close()
        if on_shutdown is not None:
            on_shutdown()

    # before the REST front (team mode forwards every other /api/v1 path to a service)
    routers = [build_session_router(verifier, tokens_managed=store is not None and verifier is not None), *rest]
    if store is not None and verifier is not None:
        routers.insert(0, build_admin_router(store, profiles=list(settings.policy.profiles), forget=verifier.forget))

    async def tools_for(caller: AccessToken | None) -> list[str] | None:
        return gateway.policy.callable_names(await gateway.tools(), caller)

    guard = rest_auth(verifier, tools_for)
    app = new_app(
        title="bagmcp gateway",
        lifespan=lifespan,
        routers=routers,
        guard=guard,
        allowed_hosts=settings.http.allowed_hosts,
        statuses=[*ADMIN_STATUSES, *UPLOAD_STATUSES, *statuses],
    )

    shared_redis = redis_client(settings.redis_url) if settings.redis_url is not None else None

    @app.get("/readyz")
    def readyz() -> JSONResponse:
        """Each upstream, and Redis in team mode, up or down, and the stores a service reports down (S3 for the
        bag-store, as it said at the catalog's last look); the reasons go to the gateway's log, not to
        unauthenticated callers."""
        status = {name: "up" if state.up else "down" for name, state in catalog.states.items()}
        for name, up in status.items():
            gateway.metrics.upstream_up.labels(name).set(1 if up == "up" else 0)
        redis_up = shared_redis is None or answers(shared_redis)
        stores_down = down_dependencies({name: state.dependencies for name, state in catalog.states.items()})
        ready = all(s == "up" for s in status.values()) and not catalog.conflicts and redis_up and not stores_down
        body: dict[str, object] = {
            "ready": ready,
            "upstreams": status,
            "tools": len(catalog.tools),
            "conflicts": len(catalog.conflicts),
        }
        if shared_redis is not None:
            body["redis"] = "up" if redis_up else "down"
        if stores_down:  # e.g. {"bag-store": ["s3"]}: the service answers, the store it needs does not
            body["stores_down"] = stores_down
        return JSONResponse(body, status_code=200 if ready else 503)

    @app.get("/metrics", dependencies=[Depends(guard)])
    def metrics() -> Response:
        return Response(gateway.metrics.exposition(), media_type=gateway.metrics.content_type)

    app.add_middleware(UploadGuard, limits=settings.uploads)
    install_console(app, token_required=verifier is not None)
    install_lab_page(app)
    app.mount("/", UniformErrors(mcp_app))
    return app
