"""An ASGI wrapper that gives the MCP endpoint's own 401/403 answers (made by the SDK's auth middleware), and the
404/405 of any path no route takes (everything unmatched falls through to the MCP app mounted at ``/``, whose
Starlette router answered ``text/plain`` "Not Found"), the project's one error shape,
``{"error": {"code", "message"}}``, keeping their headers."""

from __future__ import annotations

import json
from collections.abc import Awaitable, Callable, MutableMapping
from typing import Any

Scope = MutableMapping[str, Any]
Message = MutableMapping[str, Any]
Receive = Callable[[], Awaitable[Message]]
Send = Callable[[Message], Awaitable[None]]
App = Callable[[Scope, Receive, Send], Awaitable[None]]
_CODES = {401: "unauthorized", 403: "forbidden", 404: "not_found", 405: "method_not_allowed"}


def _default_message(status: int, scope: Scope) -> str:
    where = f"{scope.get('method', 'GET')} {scope.get('path', '/')}"
    if status == 401:
        return "a valid bearer token is required"
    if status == 403:
        return "this token may not do that"
    if status == 404:
        return f"nothing answers {where}: MCP is at /mcp, the REST API under /api/v1 (documented at /docs)"
    return f"{scope.get('path', '/')} does not take {scope.get('method', 'GET')}"


def _reshaped(body: bytes, status: int, scope: Scope) -> bytes:
    try:
        found = json.loads(body or b"{}")
    except ValueError:
        found = {}
    if isinstance(found, dict) and isinstance(found.get("error"), dict):
        return body  # already in the project's shape
    message = found.get("error_description") or found.get("error") if isinstance(found, dict) else None
    if status in (404, 405):
        message = None  # Starlette's "Not Found" says nothing a caller can act on
    text = str(message or _default_message(status, scope))
    return json.dumps({"error": {"code": _CODES[status], "message": text}}).encode()


class UniformErrors:
    def __init__(self, app: App) -> None:
        self._app = app

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http":
            await self._app(scope, receive, send)
            return
        held: Message | None = None
        parts: list[bytes] = []

        async def relay(message: Message) -> None:
            nonlocal held
            if message["type"] == "http.response.start" and message["status"] in _CODES:
                held = message
                return
            if held is None:
                await send(message)
                return
            parts.append(message.get("body", b""))
            if message.get("more_body", False):
                return
            body = _reshaped(b"".join(parts), held["status"], scope)
            headers = [
                (k, v) for k, v in held.get("headers", []) if k.lower() not in (b"content-length", b"content-type")
            ]
            headers += [(b"content-type", b"application/json"), (b"content-length", str(len(body)).encode())]
            await send({**held, "headers": headers})
            await send({"type": "http.response.body", "body": body})

        await self._app(scope, receive, relay)
