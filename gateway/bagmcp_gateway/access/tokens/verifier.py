"""Who a bearer token is: an API token (looked up by its hash, cached briefly) or a JWT from the team's
identity provider (checked against its JWKS, issuer and audience).

Each kind owns its jobs under its own namespace (the ``owner`` claim): ``token:<name>`` for an API token,
``static:<name>`` for a token given to the server at start, ``jwt:<issuer>:<sub>`` for a JWT, so a JWT whose
subject is alice never reads API token alice's jobs."""

from __future__ import annotations

import time
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, Literal

import anyio
import jwt
from mcp.server.auth.provider import AccessToken

from bagmcp_gateway.access.tokens.models import SCOPES, TokenRecord, same_hash, token_hash
from bagmcp_gateway.access.tokens.store import TokenStore

CACHE_S = 5.0
CACHE_ENTRIES = 10_000  # wrong tokens are cached too: a flood of them must not grow memory without end


@dataclass(frozen=True)
class JwtSettings:
    """``scope`` (space separated) or ``scp`` carry the scopes; ``bagmcp_profile`` names a tool profile."""

    jwks_url: str
    issuer: str
    audience: str | None = None


TokenKind = Literal["token", "static"]


def access_of(record: TokenRecord, secret: str, kind: TokenKind = "token") -> AccessToken:
    owner = f"{kind}:{record.name}"
    claims = {"profile": record.profile, "allow": record.allow, "deny": record.deny, "owner": owner}
    expires = int(record.expires_at) if record.expires_at is not None else None
    return AccessToken(
        token=secret, client_id=record.name, scopes=list(record.scopes), expires_at=expires, claims=claims
    )


class GatewayVerifier:
    """The gateway's token check (the SDK's TokenVerifier protocol), also used by the REST routes."""

    def __init__(
        self,
        store: TokenStore | None,
        *,
        static: dict[str, TokenRecord] | None = None,
        jwt_settings: JwtSettings | None = None,
    ) -> None:
        self._store = store
        self._static = static or {}
        self._jwt = jwt_settings
        self._jwks = jwt.PyJWKClient(jwt_settings.jwks_url, cache_keys=True, lifespan=300) if jwt_settings else None
        self._cache: dict[str, tuple[float, TokenRecord | None]] = {}

    def forget(self) -> None:
        """Drop cached lookups (after a revoke on this replica; other replicas follow within CACHE_S)."""
        self._cache.clear()

    async def verify_token(self, token: str) -> AccessToken | None:
        if self._jwks is not None and token.count(".") == 2:
            return await anyio.to_thread.run_sync(self._verify_jwt, token)
        digest = token_hash(token)
        kind: TokenKind = "static" if digest in self._static else "token"
        record = await self._record(digest)
        if record is None or record.expired():
            return None
        return access_of(record, token, kind)

    async def _record(self, digest: str) -> TokenRecord | None:
        """The record whose hash is ``digest``: found by hash, then compared in constant time."""
        record = self._static.get(digest) or await self._stored(digest)
        return record if record is not None and same_hash(record.hash, digest) else None

    async def _stored(self, digest: str) -> TokenRecord | None:
        cached = self._cache.get(digest)
        if cached is not None and time.monotonic() - cached[0] < CACHE_S:
            return cached[1]
        record = await anyio.to_thread.run_sync(self._store.by_hash, digest) if self._store is not None else None
        if len(self._cache) >= CACHE_ENTRIES:
            self._cache.clear()
        self._cache[digest] = (time.monotonic(), record)
        return record

    def _verify_jwt(self, token: str) -> AccessToken | None:
        assert self._jwks is not None
        assert self._jwt is not None
        try:
            key = self._jwks.get_signing_key_from_jwt(token)
            claims = jwt.decode(
                token,
                key.key,
                algorithms=["RS256", "ES256", "PS256", "EdDSA"],
                issuer=self._jwt.issuer,
                audience=self._jwt.audience,
                options={"require": ["exp", "iss", "sub"], "verify_aud": self._jwt.audience is not None},
            )
        except jwt.PyJWTError:
            return None
        subject = str(claims["sub"]).strip()
        if not subject:  # an empty subject names nobody: it must not become some shared owner
            return None
        owner = f"jwt:{claims['iss']}:{subject}"
        extra = {"profile": claims.get("bagmcp_profile"), "allow": [], "deny": [], "iss": claims["iss"], "owner": owner}
        return AccessToken(
            token=token,
            client_id=subject,
            scopes=jwt_scopes(claims),
            expires_at=int(claims["exp"]),
            subject=subject,
            claims=extra,
        )


def jwt_scopes(claims: Mapping[str, Any]) -> list[str]:
    """The bagmcp scopes a JWT grants: ``scope`` (space separated, OAuth 2) when present, else ``scp`` (a list,
    as Azure AD and Okta send it, or a space-separated string); names bagmcp does not know are dropped."""
    granted = claims["scope"] if "scope" in claims else claims.get("scp", [])
    if isinstance(granted, str):
        listed = granted.split()
    elif isinstance(granted, list):
        listed = [str(s) for s in granted]
    else:
        listed = []
    return [s for s in SCOPES if s in listed]
