"""MCP Apps viewers (extension ``io.modelcontextprotocol/ui``): the ``ui://`` document a service serves, the
``_meta`` a tool carries to point at it, and where a tool result carries the data the viewer draws.

One document draws every kind of view (time series, XY, trajectory, scan, histogram) with the same
scripts as the web console (``static/views``); hosts cache it per URI. It is 84 KB (32 KB gzipped) with
uPlot inlined, built once per process.

A result's view data travels in ``_meta["bagmcp/view"]``, not in ``content`` or ``structuredContent``:
clients without Apps get today's PNG and text unchanged, and the gateway drops the key for callers that
did not advertise the extension (``without_view_data``)."""

from __future__ import annotations

from typing import Any

import mcp.types as types
from mcp.server.apps import APP_MIME_TYPE
from mcp.server.mcpserver import MCPServer
from mcp.server.mcpserver.resources import TextResource

from bagmcp_kit.web.assets import bundle

VIEW_META_KEY = "bagmcp/view"  # on a result: the data to draw
VIEWS_META_KEY = "bagmcp/views"  # on a request from the gateway: its caller draws views
VIEW_STYLES = ("vendor/uPlot.min.css", "views/views.css")
VIEW_SCRIPTS = (
    "vendor/uPlot.iife.min.js",
    "views/dom.js",
    "views/format.js",
    "views/timeseries.js",
    "views/trajectory.js",
    "views/polar.js",
    "views/histogram.js",
    "views/table.js",
)
_VIEWER_BODY = (
    '<main id="view" class="bv-viewer" aria-live="polite"><p class="bv-muted">Waiting for the tool result…</p></main>'
)


def viewer_uri(service: str) -> str:
    return f"ui://{service}/viewer.html"


def viewer_document() -> str:
    """The ``ui://`` viewer: the shared views plus the Apps bridge, in one document."""
    return bundle(
        title="bagmcp viewer",
        styles=VIEW_STYLES,
        scripts=(*VIEW_SCRIPTS, "apps/bridge.js", "apps/viewer.js"),
        body=_VIEWER_BODY,
    )


def ui_meta(uri: str) -> dict[str, Any]:
    """A tool's ``_meta`` pointing at its viewer."""
    return {"ui": {"resourceUri": uri}}


def add_viewer(server: MCPServer, service: str) -> str:
    """Serve the viewer document at ``ui://<service>/viewer.html`` (the host applies its own CSP; ours
    asks for no outside domain). Returns the URI."""
    uri = viewer_uri(service)
    resource = TextResource(
        uri=uri,
        name=f"{service}-viewer",
        title=f"{service} viewer",
        description="Interactive view of this service's plot and analysis results (MCP Apps).",
        mime_type=APP_MIME_TYPE,
        meta={"ui": {"csp": {}, "prefersBorder": True}},
        text=viewer_document(),
    )
    server.add_resource(resource)
    return uri


def with_view(meta: dict[str, Any] | None, view: dict[str, Any]) -> dict[str, Any]:
    """A result ``_meta`` with ``view`` (a ``{"kind": ...}`` dict of plain JSON) added."""
    return {**(meta or {}), VIEW_META_KEY: view}


def asking_for_views(meta: dict[str, Any]) -> dict[str, Any]:
    """Request ``_meta`` (the gateway's to a service) saying the caller draws views."""
    return {**meta, VIEWS_META_KEY: True}


def without_view_data(result: dict[str, Any]) -> dict[str, Any]:
    """A wire-form tool result without the view data (for a caller that does not render Apps)."""
    meta = result.get("_meta")
    if not isinstance(meta, dict) or VIEW_META_KEY not in meta:
        return result
    kept = {k: v for k, v in meta.items() if k != VIEW_META_KEY}
    trimmed = {k: v for k, v in result.items() if k != "_meta"}
    return {**trimmed, "_meta": kept} if kept else trimmed


def without_viewer(tool: types.Tool) -> types.Tool:
    """``tool`` as a client without Apps is shown it: as before viewers existed (no ``_meta.ui``)."""
    if not tool.meta or "ui" not in tool.meta:
        return tool
    kept = {k: v for k, v in tool.meta.items() if k != "ui"}
    return tool.model_copy(update={"meta": kept or None})
