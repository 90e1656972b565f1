"""Creating, listing and revoking tokens: plain functions over a store, and the admin REST routes
(``/api/v1/tokens``, admin scope) that `bagmcp token --url` calls."""

from __future__ import annotations

import time
from collections.abc import Callable, Collection

from fastapi import APIRouter, Response
from pydantic import BaseModel, Field

from bagmcp_gateway.access.tokens.models import (
    SCOPES,
    NewToken,
    Scope,
    TokenInfo,
    TokenRecord,
    check_name,
    new_secret,
    parse_duration_s,
    token_hash,
)
from bagmcp_gateway.access.tokens.store import TokenStore
from bagmcp_shared.errors import ArgumentError, BagmcpError


class TokenNotFoundError(BagmcpError):
    """No token has this name."""


def _read_only() -> list[Scope]:
    return ["read"]


class TokenRequest(BaseModel):
    """What a new token may do; ``expires`` is a duration such as 30d (None: never)."""

    name: str
    scopes: list[Scope] = Field(default_factory=_read_only)
    profile: str | None = None
    allow: list[str] = Field(default_factory=list)
    deny: list[str] = Field(default_factory=list)
    expires: str | None = None


def create_token(store: TokenStore, request: TokenRequest, *, profiles: Collection[str]) -> NewToken:
    """Store a new token's hash and return the secret (shown once)."""
    check_name(request.name)
    if not request.scopes:
        raise ArgumentError(f"a token needs at least one scope: {', '.join(SCOPES)}")
    if request.profile is not None and request.profile not in profiles:
        raise ArgumentError(f"no tool profile {request.profile!r}; profiles: {', '.join(sorted(profiles))}")
    expires_at = time.time() + parse_duration_s(request.expires) if request.expires else None
    secret = new_secret()
    record = TokenRecord(
        name=request.name,
        hash=token_hash(secret),
        scopes=sorted(set(request.scopes), key=SCOPES.index),
        profile=request.profile,
        allow=request.allow,
        deny=request.deny,
        expires_at=expires_at,
    )
    store.add(record)
    return NewToken(name=record.name, token=secret, scopes=record.scopes, profile=record.profile, expires_at=expires_at)


def list_tokens(store: TokenStore) -> list[TokenInfo]:
    return [TokenInfo.of(r) for r in store.all()]


def revoke_token(store: TokenStore, name: str) -> None:
    if not store.revoke(name):
        raise TokenNotFoundError(f"no token named {name!r} (bagmcp token list shows them)")


def build_admin_router(store: TokenStore, *, profiles: Collection[str], forget: Callable[[], None]) -> APIRouter:
    """The routes behind `bagmcp token ... --url`; ``forget`` drops cached verifications after a revoke."""
    router = APIRouter(prefix="/api/v1")

    @router.post("/tokens", status_code=201)
    def create(request: TokenRequest) -> NewToken:
        return create_token(store, request, profiles=profiles)

    @router.get("/tokens")
    def listed() -> list[TokenInfo]:
        return list_tokens(store)

    @router.delete("/tokens/{name}", status_code=204)
    def revoke(name: str) -> Response:
        revoke_token(store, name)
        forget()
        return Response(status_code=204)

    return router
