"""The Lab's page at ``/lab`` (public, like the console's: it holds no data). Its API under /api/v1/lab is the
Lab's own: in process when embedded, or the Lab service the gateway forwards to in team mode."""

from __future__ import annotations

from fastapi import FastAPI

from bagmcp_kit.web.pages import web_router

LAB_PAGES = {"/lab": "lab/index.html"}


def install_lab_page(app: FastAPI) -> None:
    """Add the page; call before the MCP app is mounted at ``/`` (routes match in order)."""
    app.include_router(web_router(LAB_PAGES))
