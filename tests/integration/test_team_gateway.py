"""The team gateway over real HTTP: tokens and scopes, profiles and allow/deny lists, revocation and
expiry, JWTs, rate limits, metrics and audit, answer caps, an upstream that stops and comes back, a
start-up name collision, and two replicas sharing one Redis."""

from __future__ import annotations

import json
import os
import subprocess
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import anyio
import httpx
import pytest
from cryptography.hazmat.primitives.asymmetric import rsa
from mcp import Client

from bagmcp_gateway.access.profiles import CORE_TOOLS
from bagmcp_kit.fetch_meta import FETCHED_META_KEY
from tests.fixtures.bagfactory import BagKind, write_chatter_bag
from tests.fixtures.identity_provider import jwks_server, signed_jwt
from tests.fixtures.mcp_client import call, call_error, http_client
from tests.fixtures.processes import BIN, http_ok, service, wait_until
from tests.fixtures.servers import free_port
from tests.integration.stack import TOKEN, Stack, bagmcp, gateway_env, new_token, run_gateway

pytestmark = pytest.mark.anyio
CORE = set(CORE_TOOLS)
CORE_READ = CORE - {"filter_bag"}  # filter_bag creates a bag: it needs the upload scope, which readers lack


async def tool_names(url: str, token: str) -> list[str]:
    async with http_client(f"{url}/mcp", token) as client:
        return [t.name for t in (await client.list_tools()).tools]


def test_no_or_a_wrong_token_is_401_with_the_protected_resource_metadata(stack: Stack) -> None:
    for headers in ({}, {"Authorization": "Bearer wrong"}):
        refused = httpx.post(
            f"{stack.url}/mcp", json={"jsonrpc": "2.0", "id": 1, "method": "tools/list"}, headers=headers
        )
        assert refused.status_code == 401
        assert refused.headers["www-authenticate"].startswith("Bearer")
        assert refused.json()["error"]["code"] == "unauthorized"
    metadata = httpx.get(f"{stack.url}/.well-known/oauth-protected-resource/mcp").json()
    assert metadata["resource"].endswith("/mcp")
    assert "read" in metadata["scopes_supported"]
    assert httpx.get(f"{stack.url}/api/v1/bags").status_code == 401


def test_scopes_gate_the_rest_routes_and_the_mcp_endpoint(stack: Stack) -> None:
    reader = new_token(stack, "reader-scopes", "--scopes", "read")
    uploader = new_token(stack, "uploader-scopes", "--scopes", "upload")
    as_reader = {"Authorization": f"Bearer {reader}"}
    assert httpx.get(f"{stack.url}/api/v1/bags", headers=as_reader).status_code == 200
    upload = httpx.post(f"{stack.url}/api/v1/bags", params={"filename": "x.bag"}, content=b"x", headers=as_reader)
    assert (upload.status_code, upload.json()["error"]["code"]) == (403, "forbidden")
    assert httpx.delete(f"{stack.url}/api/v1/bags/nothing", headers=as_reader).status_code == 403
    assert httpx.get(f"{stack.url}/api/v1/tokens", headers=as_reader).status_code == 403
    no_read = httpx.post(
        f"{stack.url}/mcp",
        json={"jsonrpc": "2.0", "id": 1, "method": "tools/list"},
        headers={"Authorization": f"Bearer {uploader}"},
    )
    assert no_read.status_code == 403


async def test_a_core_token_sees_the_core_tools_in_under_6000_characters_and_is_refused_the_rest(
    stack: Stack,
) -> None:
    core = new_token(stack, "small-model", "--profile", "core")
    async with http_client(f"{stack.url}/mcp", core) as client:
        tools = (await client.list_tools()).tools
        assert {t.name for t in tools} == CORE_READ
        listed = [t.model_dump(mode="json", by_alias=True, exclude_none=True) for t in tools]
        size = len(json.dumps({"tools": listed}, separators=(",", ":")))  # as on the wire
        assert size < 6000
        refused = await call_error(client, "analyze_logs", bag="x")
        assert "not enabled for this token" in refused
    listing = bagmcp("tools", "--profile", "core", "--json")
    assert listing.returncode == 0, listing.stderr
    assert set(json.loads(listing.stdout)["tools"]) == CORE


async def test_allow_and_deny_globs_hide_tools_and_refuse_their_calls(stack: Stack) -> None:
    no_plots = new_token(stack, "no-plots", "--deny", "plot_*", "--deny", "compare_runs")
    names = await tool_names(stack.url, no_plots)
    assert not [n for n in names if n.startswith("plot_") or n == "compare_runs"]
    assert "analyze_trajectory" in names
    only_bags = new_token(stack, "only-bags", "--allow", "list_bags", "--allow", "bag_info")
    assert sorted(await tool_names(stack.url, only_bags)) == ["bag_info", "list_bags"]
    async with http_client(f"{stack.url}/mcp", no_plots) as client:
        assert "not enabled" in await call_error(client, "plot_2d", bag="x")
    reader = new_token(stack, "reader-tools", "--scopes", "read")
    assert "filter_bag" not in await tool_names(stack.url, reader)  # it creates bags: upload scope
    artifact = f"{stack.url}/api/v1/artifacts/0123456789abcdef01234567"  # REST through the proxy: the same rule
    assert httpx.get(artifact, headers={"Authorization": f"Bearer {no_plots}"}).status_code == 403
    assert httpx.get(artifact, headers={"Authorization": f"Bearer {TOKEN}"}).status_code == 404
    as_only_bags = {"Authorization": f"Bearer {only_bags}"}
    assert httpx.get(f"{stack.url}/api/v1/bags", headers=as_only_bags).status_code == 200
    assert httpx.get(f"{stack.url}/api/v1/bags/nothing/download", headers=as_only_bags).status_code == 403


async def test_a_revoked_and_an_expired_token_are_refused(stack: Stack) -> None:
    doomed = new_token(stack, "doomed")
    assert await tool_names(stack.url, doomed)
    listed = bagmcp("token", "list", "--url", stack.url, "--token", TOKEN, "--json")
    entry = next(t for t in json.loads(listed.stdout) if t["name"] == "doomed")
    assert "token" not in entry
    assert "hash" not in entry
    assert bagmcp("token", "revoke", "doomed", "--url", stack.url, "--token", TOKEN).returncode == 0
    headers = {"Authorization": f"Bearer {doomed}"}
    assert httpx.get(f"{stack.url}/api/v1/bags", headers=headers).status_code == 401
    brief = new_token(stack, "brief", "--expires", "1s")
    await anyio.sleep(1.5)
    assert httpx.get(f"{stack.url}/api/v1/bags", headers={"Authorization": f"Bearer {brief}"}).status_code == 401


async def test_metrics_count_calls_and_audit_records_name_the_token(stack: Stack) -> None:
    metered = new_token(stack, "metered")
    async with http_client(f"{stack.url}/mcp", metered) as client:
        for _ in range(3):
            await call(client, "list_bags")
    admin = {"Authorization": f"Bearer {TOKEN}"}
    assert httpx.get(f"{stack.url}/metrics", headers={"Authorization": f"Bearer {metered}"}).status_code == 403
    text = httpx.get(f"{stack.url}/metrics", headers=admin).text
    prefix = 'bagmcp_gateway_calls_total{outcome="ok",tool="list_bags"'
    line = next(row for row in text.splitlines() if row.startswith(prefix))
    assert float(line.rsplit(" ", 1)[1]) >= 3
    assert "bagmcp_gateway_call_seconds_bucket" in text

    def audited() -> bool:
        lines = (stack.logs / "gateway.log").read_text(errors="replace").splitlines()
        records = [json.loads(row) for row in lines if row.startswith('{"token":"metered"')]
        return len(records) >= 3 and all(r["tool"] == "list_bags" and r["outcome"] == "ok" for r in records)

    wait_until(audited, timeout_s=10, what="three audit records of the metered token")


async def test_a_calls_audit_record_says_the_bytes_its_service_fetched_from_s3(stack: Stack, tmp_path: Path) -> None:
    """A first read of a bag fetches blocks from S3 into the bag-store's cache; the same read again fetches
    nothing. The answer says so in ``_meta`` and the gateway's audit line carries the figure."""
    fetching = new_token(stack, "fetching")
    name = str(stack.upload_ok(write_chatter_bag(tmp_path, count=2000, name="fetched"))["name"])
    await stack.wait_ready([name])
    fetched = []
    async with http_client(f"{stack.url}/mcp", fetching) as client:
        for _ in range(2):
            result = await client.call_tool("get_message_at_time", {"bag": name, "topic": "/chatter", "time": 1.0})
            assert not result.is_error
            fetched.append((result.meta or {}).get(FETCHED_META_KEY))
    size = sum(f.stat().st_size for f in tmp_path.rglob("*.db3"))
    first, again = fetched
    assert isinstance(first, int)
    assert 0 < first <= size + 1_048_576  # at most the file and a block
    assert again is None  # from the block cache

    def audited() -> list[dict[str, Any]]:
        lines = (stack.logs / "gateway.log").read_text(errors="replace").splitlines()
        return [json.loads(row) for row in lines if row.startswith('{"token":"fetching"')]

    wait_until(lambda: len(audited()) >= 2, timeout_s=10, what="two audit records of the fetching token")
    assert [r.get("fetched_bytes") for r in audited()] == [first, None]


@pytest.fixture(scope="module")
def limited(stack: Stack) -> Iterator[str]:
    port = free_port()
    extra = {"BAGMCP_RATE_LIMIT_PER_S": "2", "BAGMCP_RATE_BURST": "3", "BAGMCP_MAX_ANSWER_CHARS": "1500"}
    with run_gateway(stack, "gateway-limited", port, extra):
        yield f"http://127.0.0.1:{port}"


async def test_a_rate_limit_trips_with_a_retry_time_and_recovers(stack: Stack, limited: str) -> None:
    token = new_token(stack, "hasty")
    async with http_client(f"{limited}/mcp", token) as client:
        answers = [await client.call_tool("list_bags", {"limit": 1}) for _ in range(4)]
        assert [a.is_error for a in answers] == [False, False, False, True]
        assert answers[3].structured_content is not None
        wait = answers[3].structured_content["retryAfterSeconds"]
        assert 0 < wait <= 1
        await anyio.sleep(wait + 0.05)
        assert not (await client.call_tool("list_bags", {"limit": 1})).is_error


async def test_a_large_answer_is_cut_with_a_note_and_its_structured_content_stays_whole(
    stack: Stack, limited: str, uploaded: dict[BagKind, dict[str, Any]]
) -> None:
    async with http_client(f"{limited}/mcp", new_token(stack, "verbose")) as client:
        answer = await client.call_tool("bag_info", {"bag": uploaded["ros1"]["name"]})
    texts = [c.text for c in answer.content if c.type == "text"]
    assert sum(len(t) for t in texts[:-1]) == 1500
    assert "answer cut at 1,500" in texts[-1]
    assert answer.structured_content is not None
    assert len(answer.structured_content["topics"]) == 9


async def test_two_replicas_on_one_redis_share_tokens_jobs_and_limits(stack: Stack, chatter: str) -> None:
    port = free_port()
    with run_gateway(stack, "gateway-replica", port, {}):
        other = f"http://127.0.0.1:{port}"
        token = new_token(stack, "roamer")  # made through the first replica
        async with http_client(f"{stack.url}/mcp", token) as first, http_client(f"{other}/mcp", token) as second:
            for client in (first, second, first, second):
                assert (await call(client, "list_bags", limit=1))["total"] >= 1
            answer = await call(
                first, "search_messages", bag=chatter, topic="/chatter", condition="regex", value="7777$"
            )
            if "job" in answer:  # a job started on one replica is followed on the other
                job = await call(second, "get_job", job_id=answer["job"]["job_id"])
                assert job["kind"] == "bag_store.search"


def test_a_tool_name_two_upstreams_publish_stops_the_gateway_at_start_naming_both(stack: Stack) -> None:
    store = stack.service_urls["bag-store"]
    env = gateway_env(stack, free_port(), {"BAGMCP_UPSTREAMS": f"bag-store={store}/mcp,bag-store-copy={store}/mcp"})
    started = subprocess.run(
        [str(BIN / "python"), "-m", "bagmcp_gateway"],
        env={**os.environ, **env},
        capture_output=True,
        text=True,
        timeout=60,
        check=False,
    )
    assert started.returncode != 0
    assert "published by bag-store and bag-store-copy" in started.stderr


@pytest.fixture(scope="module")
def identity_provider() -> Iterator[tuple[str, rsa.RSAPrivateKey]]:
    with jwks_server() as provider:
        yield provider


_jwt = signed_jwt


async def test_jwts_of_the_identity_provider_are_accepted_and_others_refused(
    stack: Stack, identity_provider: tuple[str, rsa.RSAPrivateKey]
) -> None:
    jwks_url, key = identity_provider
    port = free_port()
    extra = {"BAGMCP_JWT_JWKS_URL": jwks_url, "BAGMCP_JWT_ISSUER": "https://idp.test", "BAGMCP_JWT_AUDIENCE": "bagmcp"}
    with run_gateway(stack, "gateway-jwt", port, extra):
        url = f"http://127.0.0.1:{port}"
        assert "bag_info" in await tool_names(url, _jwt(key))
        core = await tool_names(url, _jwt(key, sub="bob", bagmcp_profile="core", scope="read upload"))
        assert set(core) == CORE
        stranger = rsa.generate_private_key(public_exponent=65537, key_size=2048)
        for refused in (
            _jwt(stranger),
            _jwt(key, exp=int(time.time()) - 10),
            _jwt(key, iss="https://elsewhere.test"),
            _jwt(key, aud="another-service"),
        ):
            answer = httpx.get(f"{url}/api/v1/bags", headers={"Authorization": f"Bearer {refused}"})
            assert answer.status_code == 401
        no_scope = httpx.get(f"{url}/api/v1/bags", headers={"Authorization": f"Bearer {_jwt(key, scope='')}"})
        assert no_scope.status_code == 403
        assert "bag_info" in await tool_names(url, _jwt(key, scope=None, scp=["read"]))  # scp as the README says
        assert await tool_names(url, _jwt(key, bagmcp_profile="typo")) == []  # an unknown profile grants nothing
        no_subject = httpx.get(f"{url}/api/v1/bags", headers={"Authorization": f"Bearer {_jwt(key, sub='')}"})
        assert no_subject.status_code == 401
        assert "bag_info" in await tool_names(url, TOKEN)  # API tokens still work beside JWTs


async def test_a_stopped_upstream_leaves_the_list_and_comes_back_and_clients_are_told(
    stack: Stack, tmp_path: Path
) -> None:
    analysis_port, port = free_port(), free_port()
    analysis_url = f"http://127.0.0.1:{analysis_port}"
    env = {**stack.worker_env, "BAGMCP_PORT": str(analysis_port), "BAGMCP_DATA_DIR": str(tmp_path / "analysis")}
    command = [str(BIN / "python"), "-m", "bagmcp_analysis"]
    upstreams = f"bag-store={stack.service_urls['bag-store']}/mcp,analysis={analysis_url}/mcp"
    events: list[str] = []

    async def listen(client: Client) -> None:
        async with client.listen(tools_list_changed=True) as subscription:
            async for event in subscription:
                events.append(type(event).__name__)

    # on SIGTERM uvicorn waits for the gateway's open requests to end; it was killed at the 10 s default each time
    answering = http_ok(f"{analysis_url}/healthz")
    analysis = service("analysis-flaky", command, env=env, log_dir=tmp_path, ready=answering, stop_timeout_s=2)
    analysis.__enter__()
    # no polling (600 s): the analysis service's change stream, dropped when it stops and back when it is,
    # tells the gateway both times (before, the stop was seen only at the next poll)
    with run_gateway(stack, "gateway-flaky", port, {"BAGMCP_UPSTREAMS": upstreams, "BAGMCP_UPSTREAM_POLL_S": "600"}):
        url = f"http://127.0.0.1:{port}"
        async with http_client(f"{url}/mcp", TOKEN) as client, anyio.create_task_group() as group:
            assert "analyze_trajectory" in await tool_names(url, TOKEN)
            group.start_soon(listen, client)
            await anyio.sleep(0.5)
            analysis.__exit__(None, None, None)
            with anyio.fail_after(20):
                while "analyze_trajectory" in await tool_names(url, TOKEN):
                    await anyio.sleep(0.3)
            assert "bag_info" in await tool_names(url, TOKEN)
            assert (await call(client, "list_bags", limit=1))["offset"] == 0  # the others keep working
            assert "analysis" in await call_error(client, "analyze_trajectory", bag="x")
            ready = httpx.get(f"{url}/readyz")
            assert (ready.status_code, ready.json()["upstreams"]["analysis"]) == (503, "down")
            with service("analysis-back", command, env=env, log_dir=tmp_path, ready=answering, stop_timeout_s=2):
                with anyio.fail_after(20):
                    while "analyze_trajectory" not in await tool_names(url, TOKEN):
                        await anyio.sleep(0.3)
                with anyio.fail_after(10):
                    while len(events) < 2:
                        await anyio.sleep(0.1)
                assert events[:2] == ["ToolsListChanged", "ToolsListChanged"]  # gone, then back
                group.cancel_scope.cancel()
