"""Who a caller is: its name in audit records, and the owner its jobs and rate-limit bucket belong to."""

from __future__ import annotations

from mcp.server.auth.provider import AccessToken

from bagmcp_kit.identity import LOCAL_CALLER


def who(caller: AccessToken | None) -> str:
    """The caller's name as audit records show it (the token's name, a JWT's subject)."""
    return caller.client_id if caller is not None else LOCAL_CALLER


def owner_of(caller: AccessToken | None) -> str:
    """Who owns the caller's jobs and rate-limit bucket, namespaced by kind (``token:alice``,
    ``static:<name>``, ``jwt:<issuer>:<sub>``; ``local`` without a token), so two kinds of identity that
    share a name never share jobs."""
    if caller is None:
        return LOCAL_CALLER
    owner = (caller.claims or {}).get("owner")
    return str(owner) if owner else f"token:{caller.client_id}"
