"""Client authentication: bearer API tokens, kept only as SHA-256 hashes."""

from __future__ import annotations

import hashlib
import hmac
from collections.abc import Awaitable, Callable, Iterable

from fastapi import HTTPException, Request
from mcp.server.auth.provider import AccessToken

CLIENT_SCOPE = "bagmcp:read"


def token_hash(token: str) -> str:
    return hashlib.sha256(token.encode()).hexdigest()


class ApiTokenVerifier:
    """Accepts tokens whose SHA-256 is among the configured hashes."""

    def __init__(self, hashes: Iterable[str]) -> None:
        self._hashes = sorted(set(hashes))

    def check(self, token: str) -> bool:
        digest = token_hash(token)
        return any(hmac.compare_digest(digest, known) for known in self._hashes)

    async def verify_token(self, token: str) -> AccessToken | None:
        if not self.check(token):
            return None
        return AccessToken(token=token, client_id=f"token-{token_hash(token)[:8]}", scopes=[CLIENT_SCOPE])


def rest_auth(verifier: ApiTokenVerifier | None) -> Callable[[Request], Awaitable[None]]:
    """A FastAPI dependency requiring a valid bearer token (none required without a verifier)."""

    async def check(request: Request) -> None:
        if verifier is None:
            return
        scheme, _, token = request.headers.get("authorization", "").partition(" ")
        if scheme.lower() != "bearer" or not verifier.check(token.strip()):
            raise HTTPException(
                status_code=401,
                detail="a valid bearer token is required",
                headers={"WWW-Authenticate": 'Bearer error="invalid_token"'},
            )

    return check
