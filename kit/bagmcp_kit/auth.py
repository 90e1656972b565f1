"""Service-to-service auth: the gateway's service credential, checked for MCP and REST alike."""

from __future__ import annotations

import hmac
from collections.abc import Awaitable, Callable

from fastapi import Request
from mcp.server.auth.provider import AccessToken

from bagmcp_kit.http_errors import HttpError

SERVICE_SCOPE = "bagmcp:service"


class ServiceTokenVerifier:
    """Accepts exactly one bearer token: the service credential shared with the gateway."""

    def __init__(self, token: str) -> None:
        self._token = token

    async def verify_token(self, token: str) -> AccessToken | None:
        if hmac.compare_digest(token.encode(), self._token.encode()):
            return AccessToken(token=token, client_id="gateway", scopes=[SERVICE_SCOPE])
        return None


def rest_guard(token: str | None) -> Callable[[Request], Awaitable[None]]:
    """A FastAPI dependency that requires ``Authorization: Bearer <token>`` when a token is set."""

    async def check(request: Request) -> None:
        if token is None:
            return
        given = request.headers.get("authorization", "")
        if not hmac.compare_digest(given.encode(), f"Bearer {token}".encode()):
            raise HttpError(401, "unauthorized", "the service credential is required", bearer=True)

    return check
