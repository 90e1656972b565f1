"""The web console at ``/`` (and its files at ``/static``) for the gateway and ``bagmcp serve``: pages only;
everything they show comes from this app's REST API and MCP endpoint with the signed-in token."""

from __future__ import annotations

from fastapi import FastAPI

from bagmcp_kit.web.pages import static_app, web_router

CONSOLE_PAGES = {"/": "console/index.html"}


def install_console(app: FastAPI) -> None:
    """Add the console's routes; call before the MCP app is mounted at ``/`` (routes match in order)."""
    app.include_router(web_router(CONSOLE_PAGES))
    app.mount("/static", static_app(), name="static")
