"""`bagmcp token create|list|revoke --data DIR` on an embedded server's data directory, while `bagmcp serve`
runs: tokens made and revoked then count without a restart; the in-memory rate limit of `bagmcp serve`; REST
reads under the token's profile and allow/deny lists; a profile the server does not know grants nothing."""

from __future__ import annotations

import json
from collections.abc import Iterator
from pathlib import Path

import anyio
import httpx
import pytest

from bagmcp_cli.token_actions import tokens_file
from bagmcp_gateway.access.tokens.models import TokenRecord, token_hash
from bagmcp_gateway.access.tokens.store import FileTokenStore
from tests.fixtures.mcp_client import call_error, http_client
from tests.fixtures.processes import BIN, http_ok, service, wait_until
from tests.fixtures.servers import free_port
from tests.integration.stack import bagmcp

pytestmark = pytest.mark.anyio
ADMIN = "serve-admin-token"
CACHE_S = 5  # the verifier remembers a lookup this long


@pytest.fixture(scope="module")
def served(tmp_path_factory: pytest.TempPathFactory) -> Iterator[tuple[str, Path]]:
    """`bagmcp serve --token`, each token limited to a call every 2 s (3 at once); yields its URL and data dir."""
    folder, data, logs = (tmp_path_factory.mktemp(n) for n in ("serve-bags", "serve-data", "serve-logs"))
    port = free_port()
    url = f"http://127.0.0.1:{port}"
    command = [str(BIN / "bagmcp"), "serve", "--bags", str(folder), "--port", str(port), "--data", str(data)]
    command += ["--token", ADMIN]
    limits = {"BAGMCP_RATE_LIMIT_PER_S": "0.5", "BAGMCP_RATE_BURST": "3"}
    with service("serve-tokens", command, env=limits, log_dir=logs, ready=http_ok(f"{url}/healthz")):
        yield url, data


def _status(url: str, token: str) -> int:
    return httpx.get(f"{url}/api/v1/bags", headers={"Authorization": f"Bearer {token}"}, timeout=10).status_code


def _create(data: Path, name: str, *options: str) -> str:
    made = bagmcp("token", "create", name, *options, "--data", str(data), "--json")
    assert made.returncode == 0, made.stderr
    answer = json.loads(made.stdout)
    assert answer["name"] == name
    return str(answer["token"])


async def test_tokens_made_and_revoked_locally_count_while_the_server_runs(served: tuple[str, Path]) -> None:
    url, data = served
    assert not (data / "tokens.json").exists()  # none at start: the server reads the file as it appears
    alice = _create(data, "alice")
    assert _status(url, alice) == 200
    small = _create(data, "small", "--profile", "core", "--deny", "plot_*")
    async with http_client(f"{url}/mcp", small) as client:
        names = [t.name for t in (await client.list_tools()).tools]
    assert "bag_info" in names
    assert "get_job" in names
    assert "plot_2d" not in names
    assert "describe_topic" not in names  # not in the core profile
    listed = bagmcp("token", "list", "--data", str(data), "--json")
    assert listed.returncode == 0, listed.stderr
    tokens = {t["name"]: t for t in json.loads(listed.stdout)}
    assert sorted(tokens) == ["alice", "small"]
    assert (tokens["small"]["profile"], tokens["small"]["deny"]) == ("core", ["plot_*"])
    assert alice not in listed.stdout
    revoked = bagmcp("token", "revoke", "alice", "--data", str(data))
    assert (revoked.returncode, revoked.stdout.strip()) == (0, "token alice revoked")
    wait_until(lambda: _status(url, alice) == 401, timeout_s=CACHE_S * 2, what="the revoked token to be refused")
    assert _status(url, small) == 200
    again = bagmcp("token", "revoke", "alice", "--data", str(data))
    assert again.returncode == 1
    assert "no token named 'alice'" in again.stderr


async def test_serve_limits_each_token_s_call_rate_and_says_when_to_retry(served: tuple[str, Path]) -> None:
    url, data = served
    async with http_client(f"{url}/mcp", _create(data, "hasty")) as client:
        answers = [await client.call_tool("list_bags", {"limit": 1}) for _ in range(4)]
        assert [a.is_error for a in answers] == [False, False, False, True]
        assert answers[3].structured_content is not None
        wait = answers[3].structured_content["retryAfterSeconds"]
        assert 0 < wait <= 2
        async with http_client(f"{url}/mcp", ADMIN) as other:  # another token has its own bucket
            assert not (await other.call_tool("list_bags", {"limit": 1})).is_error
        await anyio.sleep(wait + 0.05)
        assert not (await client.call_tool("list_bags", {"limit": 1})).is_error


def _rest(url: str, token: str, path: str) -> httpx.Response:
    return httpx.get(f"{url}/api/v1/{path}", headers={"Authorization": f"Bearer {token}"}, timeout=10)


async def test_rest_reads_obey_the_token_s_profile_and_allow_deny_lists(served: tuple[str, Path]) -> None:
    """The same rule as MCP: a route is open when the token may call one of the tools that give its data."""
    url, data = served
    everything, info_only = _create(data, "everything"), _create(data, "info-only", "--allow", "bag_info")
    no_plots = _create(data, "no-plots", "--deny", "plot_*", "--deny", "compare_runs")
    artifact, query = "artifacts/0123456789abcdef01234567", "query?sql=select+1"
    assert [_rest(url, everything, p).status_code for p in ("bags", "bags/nobag", artifact, query)] == [
        200,
        404,
        404,
        200,
    ]
    refused = {p: _rest(url, info_only, p) for p in ("bags", "bags/nobag/download", artifact, query)}
    assert {p: r.status_code for p, r in refused.items()} == dict.fromkeys(refused, 403)
    assert "needs one of the tools list_bags, find_bags, query_bags" in refused["bags"].json()["error"]["message"]
    assert _rest(url, info_only, "bags/nobag").status_code == 404  # bag_info shows a bag's record: open, none here
    plots = _rest(url, no_plots, artifact)
    assert plots.status_code == 403
    assert "needs one of the tools plot_*, compare_runs" in plots.json()["error"]["message"]
    assert _rest(url, no_plots, "bags").status_code == 200


async def test_a_profile_the_server_does_not_know_grants_nothing(served: tuple[str, Path]) -> None:
    """As a replica sees a token made where another profile exists: no tool, no REST data, and a refusal
    sentence that says why (a JWT's ``bagmcp_profile`` claim goes the same way)."""
    url, data = served
    secret = "bmcp_typo-profile-token-for-this-test"
    FileTokenStore(tokens_file(data)).add(
        TokenRecord(name="typo", hash=token_hash(secret), scopes=["read"], profile="typo")
    )
    async with http_client(f"{url}/mcp", secret) as client:
        assert (await client.list_tools()).tools == []
        refusal = await call_error(client, "list_bags")
    assert "tool profile 'typo' is not one this server knows (core, full), so it may call no tool" in refusal
    assert _rest(url, secret, "bags").status_code == 403
    made = bagmcp("token", "create", "typo2", "--profile", "typo", "--data", str(data))
    assert made.returncode == 1
    assert "no tool profile 'typo'; profiles: core, full" in made.stderr


def test_the_admin_api_refuses_bad_tokens_with_400_and_a_sentence(served: tuple[str, Path]) -> None:
    url, _ = served
    admin = {"Authorization": f"Bearer {ADMIN}"}
    asked = [
        ({"name": "far", "expires": "9" * 400 + "d"}, "is too long: at most 36500d"),
        ({"name": "typo-api", "profile": "typo"}, "no tool profile 'typo'"),
        ({"name": "local"}, "is the name of another kind of caller"),
    ]
    for body, sentence in asked:
        answer = httpx.post(f"{url}/api/v1/tokens", json=body, headers=admin, timeout=10)
        assert answer.status_code == 400, answer.text
        assert sentence in answer.json()["error"]["message"]
        assert len(answer.text) < 400
