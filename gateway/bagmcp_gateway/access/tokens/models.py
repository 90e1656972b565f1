"""A token's record: who it is, what it may do, until when. The secret itself is never stored."""

from __future__ import annotations

import hashlib
import hmac
import re
import secrets
import time
from typing import Literal

from pydantic import BaseModel, Field

from bagmcp_shared.errors import ArgumentError

Scope = Literal["read", "upload", "delete", "admin"]
SCOPES: tuple[Scope, ...] = ("read", "upload", "delete", "admin")
TOKEN_PREFIX = "bmcp_"
_NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9._-]{0,63}$")
_DURATION = re.compile(r"^(\d+)\s*([smhdw])$")
_UNITS_S = {"s": 1, "m": 60, "h": 3600, "d": 86400, "w": 604800}
MAX_DURATION_S = 100 * 365 * 86400  # a token's life: at most 100 years (36500d); none for one that never expires
# Names another kind of identity shows (a static token is named token-<first 8 hex of its hash>; "local" is
# the caller without a token, "gateway" the service credential): an API token may not take them, so an
# audit line or a listing never leaves two callers under one name.
_RESERVED = re.compile(r"^(token-[0-9a-f]{8}|local|gateway)$", re.IGNORECASE)


def token_hash(token: str) -> str:
    return hashlib.sha256(token.encode()).hexdigest()


def same_hash(a: str, b: str) -> bool:
    return hmac.compare_digest(a.encode(), b.encode())


def new_secret() -> str:
    return TOKEN_PREFIX + secrets.token_urlsafe(32)


def check_name(name: str) -> str:
    if not _NAME.match(name):
        raise ArgumentError(f"token name {name!r} must be 1-64 letters, digits, '.', '_' or '-'")
    if _RESERVED.match(name):
        raise ArgumentError(
            f"token name {name!r} is the name of another kind of caller (a static token, the local user or the "
            "gateway); choose another name"
        )
    return name


def parse_duration_s(text: str) -> int:
    """``30d``, ``12h``, ``90m``, ``2w`` or ``45s`` in seconds, at most MAX_DURATION_S (a longer one would
    overflow the expiry time: 400 digits answered 500 before)."""
    match = _DURATION.match(text.strip().lower())
    if match is None:
        raise ArgumentError(f"duration {text[:64]!r} must look like 30d, 12h, 90m, 2w or 45s")
    digits, unit = match.group(1), match.group(2)
    if len(digits) > 12 or int(digits) * _UNITS_S[unit] > MAX_DURATION_S:
        raise ArgumentError(
            f"an expiry of {digits[:12]}{'...' if len(digits) > 12 else ''}{unit} is too long: at most 36500d "
            "(100 years); leave expires out for a token that never expires"
        )
    return int(digits) * _UNITS_S[unit]


class TokenRecord(BaseModel):
    """``allow``/``deny`` are tool-name globs; ``profile`` names a tool profile (None: every enabled tool)."""

    name: str
    hash: str
    scopes: list[Scope]
    profile: str | None = None
    allow: list[str] = Field(default_factory=list)
    deny: list[str] = Field(default_factory=list)
    created_at: float = Field(default_factory=time.time)
    expires_at: float | None = None

    def expired(self, now: float | None = None) -> bool:
        return self.expires_at is not None and (now or time.time()) >= self.expires_at


class TokenInfo(BaseModel):
    """A token as `bagmcp token list` shows it (never the secret or its hash)."""

    name: str
    scopes: list[Scope]
    profile: str | None
    allow: list[str]
    deny: list[str]
    created_at: float
    expires_at: float | None
    expired: bool

    @classmethod
    def of(cls, record: TokenRecord) -> TokenInfo:
        return cls(**record.model_dump(exclude={"hash"}), expired=record.expired())


class NewToken(BaseModel):
    """What `bagmcp token create` prints once: the secret and what it may do."""

    name: str
    token: str
    scopes: list[Scope]
    profile: str | None
    expires_at: float | None
