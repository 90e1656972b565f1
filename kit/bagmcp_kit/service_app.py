"""The FastAPI skeleton every bagmcp app shares (errors in one shape, guarded REST routes, /healthz),
``create_service_app`` for a service (its MCP server at /mcp, REST under /api/v1) and ``serve``."""

from __future__ import annotations

import contextlib
from collections.abc import AsyncIterator, Awaitable, Callable, Sequence
from contextlib import AbstractAsyncContextManager

import uvicorn
from fastapi import APIRouter, Depends, FastAPI, Request
from mcp.server.mcpserver import MCPServer
from mcp.server.transport_security import TransportSecuritySettings

from bagmcp_kit.access_log import redact_access_log
from bagmcp_kit.auth import rest_guard
from bagmcp_kit.error_shape import UniformAuthErrors
from bagmcp_kit.host_check import HostAllowList
from bagmcp_kit.http_errors import StatusTable, install_error_handlers
from bagmcp_shared.settings import HttpSettings

Guard = Callable[[Request], Awaitable[None]]


def new_app(
    *,
    title: str,
    lifespan: Callable[[FastAPI], AbstractAsyncContextManager[None]],
    routers: Sequence[APIRouter],
    guard: Guard,
    allowed_hosts: Sequence[str],
    statuses: StatusTable = (),
) -> FastAPI:
    """An app with the project's error shape, ``routers`` behind ``guard``, /healthz, and every route
    answering only to ``allowed_hosts`` (DNS-rebinding protection)."""
    app = FastAPI(title=title, lifespan=lifespan)
    app.add_middleware(HostAllowList, allowed=allowed_hosts)
    install_error_handlers(app, statuses)
    for router in routers:
        app.include_router(router, dependencies=[Depends(guard)])

    @app.get("/healthz")
    def healthz() -> dict[str, bool]:
        return {"ok": True}

    return app


# Host and Origin are checked for every route, /mcp included, by the app's HostAllowList (one rule, one
# error shape); the SDK's own check would refuse an Origin that rule allows, so it is left off.
HOST_CHECK_IN_MIDDLEWARE = TransportSecuritySettings(enable_dns_rebinding_protection=False)


def create_service_app(
    *,
    title: str,
    server: MCPServer,
    routers: Sequence[APIRouter] = (),
    service_token: str | None,
    allowed_hosts: Sequence[str],
    statuses: StatusTable = (),
    on_shutdown: Callable[[], None] | None = None,
) -> FastAPI:
    """The service as an ASGI app. With ``service_token`` both MCP and REST require it."""
    security = HOST_CHECK_IN_MIDDLEWARE
    mcp_app = server.streamable_http_app(streamable_http_path="/mcp", transport_security=security)

    @contextlib.asynccontextmanager
    async def lifespan(_app: FastAPI) -> AsyncIterator[None]:
        async with server.session_manager.run():
            yield
        if on_shutdown is not None:
            on_shutdown()

    app = new_app(
        title=title,
        lifespan=lifespan,
        routers=routers,
        guard=rest_guard(service_token),
        allowed_hosts=allowed_hosts,
        statuses=statuses,
    )
    app.mount("/", UniformAuthErrors(mcp_app))
    return app


def serve(app: FastAPI, http: HttpSettings, *, log_level: str = "info") -> None:
    """Run ``app`` where ``http`` says, until interrupted (access logs never show a secret sent in a query)."""
    redact_access_log()
    uvicorn.run(app, host=http.host, port=http.port, log_level=log_level)
