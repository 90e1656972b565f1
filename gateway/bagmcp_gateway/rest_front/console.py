"""The web console at ``/`` (and its files at ``/static``) for the gateway and ``bagmcp serve``: pages only;
everything they show comes from this app's REST API and MCP endpoint with the signed-in token.

Two small JSON answers let the page start without probing routes it may not use (the browser would log
each refusal as an error): ``/console.json`` (public: is a token needed here at all) and
``/api/v1/session`` (what the presented token may do, so admin pages show only to admins)."""

from __future__ import annotations

from fastapi import APIRouter, FastAPI, Request
from fastapi.responses import JSONResponse

from bagmcp_gateway.access.tokens.models import SCOPES
from bagmcp_gateway.access.tokens.verifier import GatewayVerifier
from bagmcp_kit.web.pages import PAGE_HEADERS, static_app, web_router

CONSOLE_PAGES = {"/": "console/index.html"}


def install_console(app: FastAPI, *, token_required: bool) -> None:
    """Add the console's routes; call before the MCP app is mounted at ``/`` (routes match in order)."""
    app.include_router(web_router(CONSOLE_PAGES))
    app.mount("/static", static_app(), name="static")

    @app.get("/console.json", include_in_schema=False)
    def console_settings() -> JSONResponse:
        return JSONResponse({"token_required": token_required}, headers=PAGE_HEADERS)


def build_session_router(verifier: GatewayVerifier | None, *, tokens_managed: bool) -> APIRouter:
    """``GET /api/v1/session``: the presented token's name, scopes and profile (behind the REST guard, so
    only a valid token gets here), and whether this server manages tokens (the admin routes exist)."""
    router = APIRouter(prefix="/api/v1")

    @router.get("/session")
    async def session(request: Request) -> dict[str, object]:
        _, _, token = request.headers.get("authorization", "").partition(" ")
        access = await verifier.verify_token(token.strip()) if verifier is not None else None
        if access is None:  # no tokens on this server (loopback `bagmcp serve`): everything is allowed
            return {"name": None, "scopes": list(SCOPES), "profile": None, "tokens_managed": tokens_managed}
        profile = (access.claims or {}).get("profile")
        return {"name": access.client_id, "scopes": access.scopes, "profile": profile, "tokens_managed": tokens_managed}

    return router
