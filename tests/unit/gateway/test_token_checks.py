"""Tokens in a file, as `bagmcp token` writes them while `bagmcp serve` runs: the server's store reads the
changes through, the verifier finds a token by its hash and compares the hashes in constant time."""

from __future__ import annotations

import time
from pathlib import Path

import pytest

from bagmcp_gateway.access.tokens.admin import TokenRequest, create_token, revoke_token
from bagmcp_gateway.access.tokens.models import TokenRecord, token_hash
from bagmcp_gateway.access.tokens.store import FileTokenStore
from bagmcp_gateway.access.tokens.verifier import GatewayVerifier

pytestmark = pytest.mark.anyio
PROFILES = ["full", "core"]


def test_a_store_sees_tokens_another_process_made_and_revoked(tmp_path: Path) -> None:
    served, command_line = FileTokenStore(tmp_path / "tokens.json"), FileTokenStore(tmp_path / "tokens.json")
    assert served.all() == []
    made = create_token(command_line, TokenRequest(name="alice", profile="core"), profiles=PROFILES)
    found = served.by_hash(token_hash(made.token))
    assert found is not None
    assert (found.name, found.profile, found.scopes) == ("alice", "core", ["read"])
    assert made.token not in (tmp_path / "tokens.json").read_text()  # only its hash is kept
    revoke_token(command_line, "alice")
    assert served.by_hash(token_hash(made.token)) is None


async def test_the_verifier_accepts_a_token_by_its_hash_and_refuses_wrong_and_expired_ones(tmp_path: Path) -> None:
    store = FileTokenStore(tmp_path / "tokens.json")
    made = create_token(store, TokenRequest(name="bob", scopes=["read", "upload"]), profiles=PROFILES)
    static = TokenRecord(name="dev", hash=token_hash("dev-token"), scopes=["read", "admin"])
    verifier = GatewayVerifier(store, static={static.hash: static})
    access = await verifier.verify_token(made.token)
    assert access is not None
    assert (access.client_id, access.scopes) == ("bob", ["read", "upload"])
    dev = await verifier.verify_token("dev-token")
    assert dev is not None
    assert dev.client_id == "dev"
    assert await verifier.verify_token(made.token[:-1]) is None
    store.add(TokenRecord(name="old", hash=token_hash("old-token"), scopes=["read"], expires_at=time.time() - 1))
    assert await verifier.verify_token("old-token") is None
