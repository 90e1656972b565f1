"""The web console at ``/`` (and its files at ``/static``) for the gateway and ``bagmcp serve``: pages only;
everything they show comes from this app's REST API and MCP endpoint with the signed-in token."""

from __future__ import annotations

from fastapi import FastAPI
from fastapi.responses import JSONResponse

from bagmcp_kit.web.pages import PAGE_HEADERS, static_app, web_router

CONSOLE_PAGES = {"/": "console/index.html"}


def install_console(app: FastAPI, *, token_required: bool) -> None:
    """Add the console's routes; call before the MCP app is mounted at ``/`` (routes match in order).
    ``/console.json`` tells the page whether to ask for a token (`bagmcp serve` on loopback needs none)."""
    app.include_router(web_router(CONSOLE_PAGES))
    app.mount("/static", static_app(), name="static")

    @app.get("/console.json", include_in_schema=False)
    def console_settings() -> JSONResponse:
        return JSONResponse({"token_required": token_required}, headers=PAGE_HEADERS)
