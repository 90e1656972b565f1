"""Who a caller is, as jobs and rate limits know it: owners namespaced by kind (an API token, a static token,
a JWT's issuer and subject) so two kinds that share a name never share jobs; empty JWT subjects refused; JWT
scopes read from ``scope`` or ``scp``; a profile the server does not know grants no tool; token names another
identity shows, and absurd expiries, refused at creation."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import mcp.types as types
import pytest
from cryptography.hazmat.primitives.asymmetric import rsa

from bagmcp_gateway.access.identities import owner_of
from bagmcp_gateway.access.policy import ToolPolicy
from bagmcp_gateway.access.profiles import DEFAULT_PROFILES
from bagmcp_gateway.access.tokens.admin import TokenRequest, create_token
from bagmcp_gateway.access.tokens.models import TokenRecord, token_hash
from bagmcp_gateway.access.tokens.store import FileTokenStore
from bagmcp_gateway.access.tokens.verifier import GatewayVerifier, JwtSettings
from bagmcp_kit.arguments import READ_ONLY
from bagmcp_shared.errors import ArgumentError, JobNotFoundError
from bagmcp_shared.jobs import MemoryJobStore
from bagmcp_shared.jobs.models import Job
from bagmcp_shared.jobs.store import owned
from tests.fixtures.identity_provider import AUDIENCE, ISSUER, jwks_server, signed_jwt

pytestmark = pytest.mark.anyio
PROFILES = ["full", "core"]
DEV_TOKEN = "dev-token"


@pytest.fixture(scope="module")
def provider() -> Iterator[tuple[str, rsa.RSAPrivateKey]]:
    with jwks_server() as served:
        yield served


def _verifier(tmp_path: Path, jwks_url: str) -> tuple[GatewayVerifier, FileTokenStore]:
    store = FileTokenStore(tmp_path / "tokens.json")
    dev = TokenRecord(name=f"token-{token_hash(DEV_TOKEN)[:8]}", hash=token_hash(DEV_TOKEN), scopes=["read"])
    jwt_settings = JwtSettings(jwks_url, ISSUER, AUDIENCE)
    return GatewayVerifier(store, static={dev.hash: dev}, jwt_settings=jwt_settings), store


async def test_a_jwt_whose_subject_is_alice_does_not_own_api_token_alice_s_jobs(
    tmp_path: Path, provider: tuple[str, rsa.RSAPrivateKey]
) -> None:
    jwks_url, key = provider
    verifier, store = _verifier(tmp_path, jwks_url)
    alice = create_token(store, TokenRequest(name="alice"), profiles=PROFILES)
    api, jwt_alice, dev = [await verifier.verify_token(t) for t in (alice.token, signed_jwt(key), DEV_TOKEN)]
    assert api is not None
    assert jwt_alice is not None
    assert dev is not None
    assert (api.client_id, jwt_alice.client_id) == ("alice", "alice")  # the same name in audit lines...
    owners = [owner_of(api), owner_of(jwt_alice), owner_of(dev), owner_of(None)]
    assert owners == ["token:alice", f"jwt:{ISSUER}:alice", f"static:token-{token_hash(DEV_TOKEN)[:8]}", "local"]
    jobs = MemoryJobStore()
    job = Job.new("search", owner_of(api), {})
    jobs.put(job)
    assert owned(jobs, job.id, owner_of(api)).id == job.id
    with pytest.raises(JobNotFoundError, match="no job"):  # ...but not the same owner of jobs
        owned(jobs, job.id, owner_of(jwt_alice))


async def test_a_jwt_with_an_empty_subject_is_refused(tmp_path: Path, provider: tuple[str, rsa.RSAPrivateKey]) -> None:
    jwks_url, key = provider
    verifier, _ = _verifier(tmp_path, jwks_url)
    assert await verifier.verify_token(signed_jwt(key, sub="")) is None
    assert await verifier.verify_token(signed_jwt(key, sub="  ")) is None
    assert await verifier.verify_token(signed_jwt(key, sub="bob")) is not None


async def test_a_jwt_carrying_only_scp_gets_those_scopes(
    tmp_path: Path, provider: tuple[str, rsa.RSAPrivateKey]
) -> None:
    jwks_url, key = provider
    verifier, _ = _verifier(tmp_path, jwks_url)
    as_list = await verifier.verify_token(signed_jwt(key, scope=None, scp=["read", "upload", "openid"]))
    as_text = await verifier.verify_token(signed_jwt(key, scope=None, scp="read delete"))
    both = await verifier.verify_token(signed_jwt(key, scope="read", scp=["admin"]))  # scope wins, as the README says
    assert as_list is not None
    assert as_text is not None
    assert both is not None
    assert (as_list.scopes, as_text.scopes, both.scopes) == (["read", "upload"], ["read", "delete"], ["read"])


@pytest.mark.parametrize("name", [f"token-{token_hash(DEV_TOKEN)[:8]}", "token-0123abcd", "local", "Gateway"])
def test_a_token_name_another_identity_shows_is_refused_at_creation(tmp_path: Path, name: str) -> None:
    store = FileTokenStore(tmp_path / "tokens.json")
    with pytest.raises(ArgumentError, match="name of another kind of caller"):
        create_token(store, TokenRequest(name=name), profiles=PROFILES)
    assert store.all() == []
    assert create_token(store, TokenRequest(name="token-team"), profiles=PROFILES).name == "token-team"


@pytest.mark.parametrize("expires", ["9" * 400 + "d", "1" * 13 + "s", "36501d", "5300w"])
def test_an_absurd_expiry_is_an_argument_error_not_a_crash(tmp_path: Path, expires: str) -> None:
    store = FileTokenStore(tmp_path / "tokens.json")
    with pytest.raises(ArgumentError, match=r"must look like|is too long: at most 36500d") as refused:
        create_token(store, TokenRequest(name="far", expires=expires), profiles=PROFILES)
    assert len(str(refused.value)) < 200
    assert create_token(store, TokenRequest(name="far", expires="36500d"), profiles=PROFILES).expires_at is not None


def test_an_unknown_profile_is_refused_at_creation(tmp_path: Path) -> None:
    store = FileTokenStore(tmp_path / "tokens.json")
    with pytest.raises(ArgumentError, match="no tool profile 'typo'; profiles: core, full"):
        create_token(store, TokenRequest(name="typo", profile="typo"), profiles=PROFILES)


async def test_a_jwt_naming_an_unknown_profile_may_call_no_tool(
    tmp_path: Path, provider: tuple[str, rsa.RSAPrivateKey]
) -> None:
    jwks_url, key = provider
    verifier, _ = _verifier(tmp_path, jwks_url)
    typo = await verifier.verify_token(signed_jwt(key, bagmcp_profile="typo"))
    core = await verifier.verify_token(signed_jwt(key, bagmcp_profile="core"))
    assert typo is not None
    assert core is not None
    tools = [
        types.Tool(name=n, input_schema={"type": "object"}, annotations=READ_ONLY) for n in ("list_bags", "bag_info")
    ]
    policy = ToolPolicy()
    assert (policy.shown(tools, typo), policy.callable_names(tools, typo)) == ([], [])
    assert "tool profile 'typo' is not one this server knows (core, full)" in policy.refusal(tools[0], typo)
    replica = ToolPolicy(profiles={"full": DEFAULT_PROFILES["full"]})  # configured without the core profile
    assert [t.name for t in policy.shown(tools, core)] == ["list_bags", "bag_info"]
    assert replica.shown(tools, core) == []
