"""``create_app``: the gateway: aggregated MCP at /mcp, REST under /api/v1, /healthz, /readyz."""

from __future__ import annotations

import contextlib
from collections.abc import AsyncIterator, Callable
from dataclasses import dataclass, field

import anyio
from fastapi import APIRouter, Depends, FastAPI
from fastapi.responses import JSONResponse
from mcp.server.auth.settings import AuthSettings
from mcp.server.transport_security import TransportSecuritySettings
from pydantic import AnyHttpUrl

from bagmcp_gateway.aggregator import Routing, build_gateway_server, collect_tools
from bagmcp_gateway.auth import CLIENT_SCOPE, ApiTokenVerifier, rest_auth
from bagmcp_gateway.connections import Connections
from bagmcp_gateway.upstreams import GatewayConfigError, Upstream


@dataclass(frozen=True)
class GatewayConfig:
    """``token_hashes`` empty means no authentication (only for a loopback embedded server)."""

    upstreams: list[Upstream]
    token_hashes: list[str] = field(default_factory=list)
    public_url: str = "http://127.0.0.1:8080"
    allowed_hosts: tuple[str, ...] = ("127.0.0.1:*", "localhost:*", "[::1]:*")


def create_app(config: GatewayConfig, *, rest: APIRouter, on_shutdown: Callable[[], None] | None = None) -> FastAPI:
    """The gateway app. ``rest`` serves /api/v1 (a proxy in team mode, the bag-store's routes embedded)."""
    verifier = ApiTokenVerifier(config.token_hashes) if config.token_hashes else None
    connections = Connections(config.upstreams)
    server = build_gateway_server(config.upstreams, connections=connections)
    auth = None
    if verifier is not None:
        auth = AuthSettings(
            issuer_url=AnyHttpUrl(config.public_url),
            resource_server_url=AnyHttpUrl(f"{config.public_url}/mcp"),
            required_scopes=[CLIENT_SCOPE],
            validate_token_resource=False,
        )
    security = TransportSecuritySettings(allowed_hosts=list(config.allowed_hosts), allowed_origins=[])
    mcp_app = server.streamable_http_app(
        streamable_http_path="/mcp",
        stateless_http=True,
        json_response=False,
        transport_security=security,
        auth=auth,
        token_verifier=verifier,
    )

    @contextlib.asynccontextmanager
    async def lifespan(_app: FastAPI) -> AsyncIterator[None]:
        async with anyio.create_task_group() as group:
            await group.start(connections.run)
            async with server.session_manager.run():
                yield
            group.cancel_scope.cancel()
        if on_shutdown is not None:
            on_shutdown()

    app = FastAPI(title="bagmcp gateway", lifespan=lifespan)
    app.include_router(rest, dependencies=[Depends(rest_auth(verifier))])

    @app.get("/healthz")
    def healthz() -> dict[str, bool]:
        return {"ok": True}

    @app.get("/readyz")
    async def readyz() -> JSONResponse:
        """Per-upstream up/down (details go to the gateway's log, not to unauthenticated callers)."""
        routing = Routing()
        try:
            with anyio.move_on_after(15):
                await collect_tools(config.upstreams, routing)
        except GatewayConfigError:
            return JSONResponse({"ready": False, "error": "configuration error (see the gateway log)"}, status_code=503)
        status = {u.name: "down" if u.name in routing.down else "up" for u in config.upstreams}
        ready = not routing.down
        return JSONResponse({"ready": ready, "upstreams": status}, status_code=200 if ready else 503)

    app.mount("/", mcp_app)
    return app
