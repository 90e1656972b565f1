"""``create_app``: the bag-store FastAPI app with its MCP server at /mcp and REST under /api/v1."""

from __future__ import annotations

import contextlib
from collections.abc import AsyncIterator
from pathlib import Path

from fastapi import Depends, FastAPI
from mcp.server.auth.settings import AuthSettings
from mcp.server.transport_security import TransportSecuritySettings
from pydantic import AnyHttpUrl

from bagmcp_bag_store.api import build_router, install_error_handler
from bagmcp_bag_store.auth import SERVICE_SCOPE, ServiceTokenVerifier, rest_guard
from bagmcp_bag_store.deps import BagStoreDeps
from bagmcp_bag_store.tools import build_mcp


def create_app(
    deps: BagStoreDeps,
    *,
    upload_dir: Path,
    max_upload_bytes: int,
    service_token: str | None = None,
    public_url: str = "http://127.0.0.1:8000",
    allowed_hosts: tuple[str, ...] = ("127.0.0.1:*", "localhost:*"),
) -> FastAPI:
    """The service as an ASGI app. With ``service_token`` both MCP and REST require it."""
    auth = None
    verifier = None
    if service_token is not None:
        verifier = ServiceTokenVerifier(service_token)
        auth = AuthSettings(
            issuer_url=AnyHttpUrl(public_url),
            resource_server_url=AnyHttpUrl(f"{public_url}/mcp"),
            required_scopes=[SERVICE_SCOPE],
            validate_token_resource=False,
        )
    mcp = build_mcp(deps, token_verifier=verifier, auth=auth)
    security = TransportSecuritySettings(allowed_hosts=list(allowed_hosts), allowed_origins=[])
    mcp_app = mcp.streamable_http_app(streamable_http_path="/mcp", transport_security=security)

    @contextlib.asynccontextmanager
    async def lifespan(_app: FastAPI) -> AsyncIterator[None]:
        async with mcp.session_manager.run():
            yield

    app = FastAPI(title="bagmcp bag-store", lifespan=lifespan)
    install_error_handler(app)
    app.include_router(
        build_router(deps, upload_dir=upload_dir, max_upload_bytes=max_upload_bytes),
        dependencies=[Depends(rest_guard(service_token))],
    )

    @app.get("/healthz")
    def healthz() -> dict[str, bool]:
        return {"ok": True}

    app.mount("/", mcp_app)
    return app
