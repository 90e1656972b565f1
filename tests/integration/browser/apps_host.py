"""Serving a tool call to a viewer in a test host page: the host (apps_host.html/js) and the viewer document
are answered by Playwright's request routing on an address that never reaches the network, each with the
kind of Content-Security-Policy a real host applies (the viewer: inline code only, no network)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from playwright.sync_api import Frame, Page, Route

HERE = Path(__file__).resolve().parent
ORIGIN = "http://apps-host.test"
HOST_CSP = "default-src 'none'; script-src 'self'; style-src 'self'; frame-src 'self'; img-src data:"
VIEWER_CSP = "default-src 'none'; script-src 'unsafe-inline'; style-src 'unsafe-inline'; img-src data: blob:"


def open_viewer(page: Page, viewer_html: str, arguments: dict[str, Any], result: dict[str, Any]) -> Frame:
    """Load the host page with ``viewer_html`` in its frame and hand it this call; the viewer's frame once it
    has drawn (or shown an error)."""
    files = {
        "/apps_host.html": ("text/html", (HERE / "apps_host.html").read_text(), HOST_CSP),
        "/apps_host.js": ("text/javascript", (HERE / "apps_host.js").read_text(), HOST_CSP),
        "/host.css": ("text/css", (HERE / "host.css").read_text(), HOST_CSP),
        "/call.js": (
            "text/javascript",
            f"window.CALL = {json.dumps({'arguments': arguments, 'result': result})};",
            HOST_CSP,
        ),
        "/viewer.html": ("text/html", viewer_html, VIEWER_CSP),
    }

    def answer(route: Route) -> None:
        path = "/" + route.request.url.removeprefix(ORIGIN).lstrip("/").split("?")[0]
        if path not in files:
            route.fulfill(status=404, body="not here")
            return
        kind, body, csp = files[path]
        route.fulfill(
            status=200, body=body, headers={"Content-Type": f"{kind}; charset=utf-8", "Content-Security-Policy": csp}
        )

    page.route(f"{ORIGIN}/**", answer)
    page.goto(f"{ORIGIN}/apps_host.html")
    handle = page.wait_for_selector("#viewer")
    frame = handle.content_frame() if handle is not None else None
    assert frame is not None
    frame.wait_for_function(
        "() => (window.BagViews && window.BagViews.drawn || []).length > 0 || !!document.querySelector('.bv-error')"
    )
    return frame
