"""What every app built on the kit does at its HTTP edge: one error shape even for bugs, only allowed
Host headers (DNS rebinding), no foreign Origins, and no secrets in access logs."""

from __future__ import annotations

import contextlib
import logging
from collections.abc import AsyncIterator

import httpx
import pytest
from fastapi import APIRouter, FastAPI, Request
from fastapi.testclient import TestClient

from bagmcp_kit.access_log import RedactSecrets, redacted
from bagmcp_kit.host_check import host_allowed
from bagmcp_kit.server import new_server
from bagmcp_kit.service_app import create_service_app, new_app
from bagmcp_shared.settings import LOOPBACK_HOSTS
from tests.fixtures.mcp_client import INITIALIZE, MCP_HEADERS


@contextlib.asynccontextmanager
async def _nothing(_app: FastAPI) -> AsyncIterator[None]:
    yield


async def _open(_request: Request) -> None:
    return None


def _app() -> FastAPI:
    router = APIRouter(prefix="/api/v1")

    @router.get("/bags/{ref}/download")
    def download(ref: str) -> dict[str, str]:
        return {"bag": ref}

    @router.get("/crash")
    def crash() -> None:
        raise RuntimeError("secret internal detail")

    return new_app(title="t", lifespan=_nothing, routers=[router], guard=_open, allowed_hosts=LOOPBACK_HOSTS)


def test_a_bug_answers_500_in_the_one_error_shape_without_details() -> None:
    client = TestClient(_app(), base_url="http://127.0.0.1:8000", raise_server_exceptions=False)
    answer = client.get("/api/v1/crash")
    assert answer.status_code == 500
    assert answer.json()["error"]["code"] == "internal_error"
    assert "secret internal detail" not in answer.text
    assert "Traceback" not in answer.text


@pytest.mark.parametrize("host", ["evil.example:8000", "evil.example", "127.0.0.1.evil.example:80", ""])
def test_every_route_refuses_a_foreign_host_header_with_421(host: str) -> None:
    client = TestClient(_app(), base_url="http://127.0.0.1:8000")
    for path in ("/api/v1/bags/x/download", "/healthz"):
        answer = client.get(path, headers={"host": host})
        assert answer.status_code == 421, path
        assert answer.json()["error"]["code"] == "misdirected_request"
        assert "--allowed-host" in answer.json()["error"]["message"]


def test_loopback_names_are_answered_and_foreign_origins_refused() -> None:
    client = TestClient(_app(), base_url="http://127.0.0.1:8000")
    for host in ("127.0.0.1:8000", "localhost:1234", "[::1]:8000"):
        assert client.get("/api/v1/bags/x/download", headers={"host": host}).json() == {"bag": "x"}
    refused = client.get("/api/v1/bags/x/download", headers={"origin": "http://evil.example"})
    assert refused.status_code == 403
    assert refused.json()["error"]["code"] == "forbidden_origin"
    same = client.get("/api/v1/bags/x/download", headers={"origin": "http://127.0.0.1:8000"})
    assert same.status_code == 200


def test_host_patterns_match_a_name_with_any_port_or_exactly() -> None:
    allowed = ("bags.lab:*", "10.0.0.5:8000")
    assert host_allowed("bags.lab:8000", allowed)
    assert host_allowed("bags.lab", allowed)
    assert host_allowed("10.0.0.5:8000", allowed)
    assert not host_allowed("10.0.0.5:9000", allowed)
    assert not host_allowed("bags.lab.evil:80", allowed)
    assert not host_allowed("xbags.lab:80", allowed)


def test_secret_query_parameters_never_reach_a_log() -> None:
    assert redacted("/mcp?token=abc&x=1") == "/mcp?token=REDACTED&x=1"
    assert (
        redacted("/api/v1/bags?filename=a.bag&access_token=abc") == "/api/v1/bags?filename=a.bag&access_token=REDACTED"
    )
    assert redacted("/api/v1/bags?api_key=abc#frag") == "/api/v1/bags?api_key=REDACTED#frag"
    record = logging.LogRecord("uvicorn.access", logging.INFO, "", 0, '%s - "%s %s HTTP/%s" %d', None, None)
    record.args = ("127.0.0.1:5", "GET", "/mcp?Token=s3cr3t", "1.1", 200)
    assert RedactSecrets().filter(record)
    assert "s3cr3t" not in record.getMessage()
    forwarded = logging.LogRecord("httpx", logging.INFO, "", 0, 'HTTP Request: %s %s "%s %d %s"', None, None)
    forwarded.args = ("GET", httpx.URL("http://b:8001/api/v1/bags?token=s3cr3t&limit=1"), "HTTP/1.1", 200, "OK")
    assert RedactSecrets().filter(forwarded)
    assert (
        forwarded.getMessage() == 'HTTP Request: GET http://b:8001/api/v1/bags?token=REDACTED&limit=1 "HTTP/1.1 200 OK"'
    )


def test_mcp_takes_the_same_host_and_origin_rule_as_every_other_route() -> None:
    app = create_service_app(
        title="t", server=new_server("t", purpose="Test.", tools=[]), service_token=None, allowed_hosts=LOOPBACK_HOSTS
    )
    with TestClient(app, base_url="http://127.0.0.1:8000") as client:
        refused = client.post("/mcp", json=INITIALIZE, headers={**MCP_HEADERS, "origin": "http://evil.example"})
        assert refused.status_code == 403
        assert refused.json()["error"]["code"] == "forbidden_origin"
        same = client.post("/mcp", json=INITIALIZE, headers={**MCP_HEADERS, "origin": "http://127.0.0.1:8000"})
        assert same.status_code == 200, same.text
        assert "serverInfo" in same.text


def test_a_path_no_route_takes_answers_in_the_one_error_shape_and_names_the_right_ones() -> None:
    app = create_service_app(
        title="t", server=new_server("t", purpose="Test.", tools=[]), service_token=None, allowed_hosts=LOOPBACK_HOSTS
    )
    with TestClient(app, base_url="http://127.0.0.1:8000") as client:
        for method, path in (("GET", "/nope"), ("POST", "/api/v1/nothing"), ("DELETE", "/healthz")):
            answer = client.request(method, path)
            assert answer.status_code == 404, path
            assert answer.headers["content-type"] == "application/json"
            error = answer.json()["error"]
            assert error["code"] == "not_found"
            assert error["message"].startswith(f"nothing answers {method} {path}: MCP is at /mcp")
