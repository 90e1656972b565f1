"""Serving the web pages: HTML pages by path and the files under ``/static``, every response of theirs
with a strict Content-Security-Policy (no inline script or style, nothing from other origins).

Pages and assets are public: they hold no data; everything they show comes from the REST API and MCP
with the token the user signs in with. The app's Host/Origin rule (kit/host_check.py) covers them too."""

from __future__ import annotations

from collections.abc import Callable, Mapping

from fastapi import APIRouter
from fastapi.responses import HTMLResponse
from starlette.staticfiles import StaticFiles

from bagmcp_kit.error_shape import App, Message, Receive, Scope, Send
from bagmcp_kit.web.assets import STATIC_DIR, asset_text

CSP = "; ".join(
    (
        "default-src 'none'",
        "script-src 'self'",
        "style-src 'self'",
        "img-src 'self' blob: data:",
        "connect-src 'self'",
        "font-src 'self'",
        "manifest-src 'self'",
        "base-uri 'none'",
        "form-action 'none'",
        "frame-ancestors 'none'",
    )
)
PAGE_HEADERS = {
    "Content-Security-Policy": CSP,
    "X-Content-Type-Options": "nosniff",
    "Referrer-Policy": "no-referrer",
    "Cache-Control": "no-cache",
}


def web_router(pages: Mapping[str, str]) -> APIRouter:
    """GET routes for ``pages`` (URL path -> HTML file under ``static/``)."""
    router = APIRouter(include_in_schema=False)
    for url, relative in pages.items():
        router.add_api_route(url, _page(relative), methods=["GET"], response_class=HTMLResponse)
    return router


def _page(relative: str) -> Callable[[], HTMLResponse]:
    def page() -> HTMLResponse:
        return HTMLResponse(asset_text(relative), headers=PAGE_HEADERS)

    page.__name__ = f"page_{relative.replace('/', '_').replace('.', '_')}"
    return page


class StaticAssets:
    """``/static/...``: the files under ``static/`` with the page headers (no directory listings)."""

    def __init__(self) -> None:
        self._files = StaticFiles(directory=STATIC_DIR, html=False)

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        async def with_headers(message: Message) -> None:
            if message["type"] == "http.response.start":
                extra = [(k.lower().encode(), v.encode()) for k, v in PAGE_HEADERS.items()]
                message["headers"] = [*message.get("headers", []), *extra]
            await send(message)

        await self._files(scope, receive, with_headers)


def static_app() -> App:
    return StaticAssets()
