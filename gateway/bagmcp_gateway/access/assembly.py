"""The access parts of one gateway, made from its settings: where tokens are kept (Redis in team mode, a file
for ``bagmcp serve``, none without tokens), the verifier that checks them, and the rate limiter (shared by
the replicas through Redis, else in this process)."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from bagmcp_gateway.access.ratelimit import Limit, MemoryRateLimiter, RateLimiter, RedisRateLimiter
from bagmcp_gateway.access.tokens.models import SCOPES, TokenRecord
from bagmcp_gateway.access.tokens.store import FileTokenStore, RedisTokenStore, TokenStore
from bagmcp_gateway.access.tokens.verifier import GatewayVerifier, JwtSettings
from bagmcp_shared.redis_connection import redis_client


def token_store(redis_url: str | None, tokens_file: Path | None) -> TokenStore | None:
    if redis_url is not None:
        return RedisTokenStore(redis_client(redis_url))
    return FileTokenStore(tokens_file) if tokens_file is not None else None


def rate_limiter(limit: Limit | None, redis_url: str | None) -> RateLimiter | None:
    if limit is None:
        return None
    if redis_url is not None:
        return RedisRateLimiter(redis_client(redis_url), limit)
    return MemoryRateLimiter(limit)


def token_verifier(
    store: TokenStore | None, *, static_hashes: Sequence[str], jwt: JwtSettings | None
) -> GatewayVerifier:
    """Stored tokens, the static ones (every scope, named by their hash's start) and JWTs."""
    static = {h: TokenRecord(name=f"token-{h[:8]}", hash=h, scopes=list(SCOPES)) for h in static_hashes}
    return GatewayVerifier(store, static=static, jwt_settings=jwt)
