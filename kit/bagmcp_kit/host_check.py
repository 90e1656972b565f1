"""DNS-rebinding protection for every HTTP route of an app (MCP, REST, downloads, artifacts, health): a
request whose Host header (or, from a browser, whose Origin) is not one the server answers to is refused
with 421 (403 for the Origin) in the one error shape, before any route runs."""

from __future__ import annotations

from collections.abc import Sequence
from urllib.parse import urlsplit

from bagmcp_kit.error_shape import App, Receive, Scope, Send
from bagmcp_kit.http_errors import error_response


def host_allowed(host: str, allowed: Sequence[str]) -> bool:
    """``host`` (a Host header, ``name[:port]``) matches an entry: exactly, or ``name:*`` for any port."""
    for pattern in allowed:
        if host == pattern:
            return True
        if pattern.endswith(":*") and (host == pattern[:-2] or host.startswith(pattern[:-1])):
            return True
    return False


def _header(scope: Scope, name: bytes) -> str | None:
    for key, value in scope.get("headers", []):
        if key.lower() == name:
            return bytes(value).decode("latin-1")
    return None


class HostAllowList:
    """ASGI middleware; ``allowed`` holds ``name:port`` or ``name:*`` entries."""

    def __init__(self, app: App, allowed: Sequence[str]) -> None:
        self._app = app
        self._allowed = tuple(allowed)

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] == "http":
            host = _header(scope, b"host") or ""
            origin = _header(scope, b"origin")
            if not host_allowed(host, self._allowed):
                message = (
                    f"this server does not answer to the host name {host!r}; if clients reach it by that name, "
                    "start it with --allowed-host (or set BAGMCP_ALLOWED_HOSTS)"
                )
                await error_response(421, "misdirected_request", message)(scope, receive, send)
                return
            if origin is not None and not host_allowed(urlsplit(origin).netloc, self._allowed):
                message = "requests from web pages of other sites are refused"
                await error_response(403, "forbidden_origin", message)(scope, receive, send)
                return
        await self._app(scope, receive, send)
