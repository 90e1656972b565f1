"""Uploads (``POST /api/v1/bags``) at the gateway, proxied or embedded: each token runs at most
``per_token`` of them at once (the next one answers 429 at once, before its body is read), and an upload that
sends nothing for ``idle_s`` seconds is ended with 408. Before, 1,500 uploads held open at 1 byte per 2 s made
every other call time out; now one token holds ``per_token`` connections and an idle one ends in ``idle_s``.

Tokens are told apart by a hash of the Authorization header (the route's own check of the token runs after
this, inside the app), so a caller without a valid token is refused there as before. The counts are per
gateway process: N replicas admit N x ``per_token`` uploads of one token.

An answer sent before the body was read to its end (429, 408, or the app's own refusal, such as ``bagmcp
serve``'s 405 read_only) closes the connection: else the server kept it open for the rest of the body, which a
client trickling a byte at a time could hold forever.
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass

import anyio
from starlette.types import ASGIApp, Message, Receive, Scope, Send

from bagmcp_kit.http_errors import error_response
from bagmcp_shared.errors import BagmcpError

UPLOAD_PATH = "/api/v1/bags"
DEFAULT_IDLE_S = 60.0
DEFAULT_PER_TOKEN = 4


class UploadStalledError(BagmcpError):
    """An upload's body sent nothing for the idle time; it was ended (HTTP 408)."""


@dataclass(frozen=True)
class UploadLimits:
    idle_s: float = DEFAULT_IDLE_S
    per_token: int = DEFAULT_PER_TOKEN


def _is_upload(scope: Scope) -> bool:
    return scope["type"] == "http" and scope["method"] == "POST" and str(scope["path"]).rstrip("/") == UPLOAD_PATH


def _caller_key(scope: Scope) -> str:
    header = next((value for name, value in scope["headers"] if name == b"authorization"), b"")
    return hashlib.sha256(header).hexdigest()[:24] if header else "anonymous"


class _ClosedUnlessRead:
    """``receive`` that notes when the body has been read to its end, and ``send`` that adds ``Connection:
    close`` to an answer that comes before it."""

    def __init__(self, receive: Receive, send: Send) -> None:
        self._receive, self._send = receive, send
        self._read = False

    async def receive(self) -> Message:
        message = await self._receive()
        if message["type"] == "http.disconnect" or not message.get("more_body", False):
            self._read = True
        return message

    async def send(self, message: Message) -> None:
        if message["type"] == "http.response.start" and not self._read:
            message = {**message, "headers": [*message.get("headers", []), (b"connection", b"close")]}
        await self._send(message)


class UploadGuard:
    """ASGI middleware applying ``UploadLimits`` to uploads; every other request passes untouched."""

    def __init__(self, app: ASGIApp, limits: UploadLimits) -> None:
        self._app, self._limits = app, limits
        self._running: dict[str, int] = {}

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if not _is_upload(scope):
            await self._app(scope, receive, send)
            return
        body = _ClosedUnlessRead(receive, send)
        receive, send = body.receive, body.send
        caller = _caller_key(scope)
        running = self._running.get(caller, 0)
        if running >= self._limits.per_token:
            message = (
                f"this token has {running} uploads running, the most it may at once; "
                "wait for one to finish, then send this one again"
            )
            await error_response(429, "too_many_uploads", message)(scope, receive, send)
            return
        self._running[caller] = running + 1
        try:
            await self._app(scope, self._paced(receive), send)
        finally:
            self._running[caller] -= 1
            if not self._running[caller]:
                del self._running[caller]

    def _paced(self, receive: Receive) -> Receive:
        """``receive`` that raises UploadStalledError (answered 408) when the client sends nothing for idle_s."""
        idle_s = self._limits.idle_s

        async def paced() -> Message:
            try:
                with anyio.fail_after(idle_s):
                    return await receive()
            except TimeoutError:
                raise UploadStalledError(
                    f"the upload sent nothing for {idle_s:g} s, so it was ended; check the connection and send "
                    "it again (the server ends an upload after BAGMCP_UPLOAD_IDLE_S seconds without a byte)"
                ) from None

        return paced
