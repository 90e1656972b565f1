"""`bagmcp serve` over real HTTP answers only to the host names it is reached by (DNS-rebinding protection
on every route, MCP, REST and downloads alike); a server on every address is reached by the names given with
--allowed-host or BAGMCP_ALLOWED_HOSTS."""

from __future__ import annotations

import json
from collections.abc import Iterator
from pathlib import Path

import httpx
import pytest

from tests.fixtures.bagfactory import BagKind
from tests.fixtures.inprocess import copy_bags
from tests.fixtures.mcp_client import INITIALIZE, MCP_HEADERS
from tests.fixtures.processes import BIN, HTTP, http_ok, service, wait_until
from tests.fixtures.servers import free_port


@pytest.fixture(scope="module")
def folder(scenario_bags: dict[BagKind, Path], tmp_path_factory: pytest.TempPathFactory) -> Path:
    return copy_bags([scenario_bags["ros1"]], tmp_path_factory.mktemp("bags"))


def _serve(folder: Path, port: int, data: Path, *extra: str) -> list[str]:
    return [str(BIN / "bagmcp"), "serve", "--bags", str(folder), "--port", str(port), "--data", str(data), *extra]


@pytest.fixture(scope="module")
def loopback(folder: Path, tmp_path_factory: pytest.TempPathFactory) -> Iterator[str]:
    """A tokenless server on loopback, with its bag ingested."""
    port, work = free_port(), tmp_path_factory.mktemp("serve")
    url = f"http://127.0.0.1:{port}"
    with service("serve-loopback", _serve(folder, port, work), env={}, log_dir=work, ready=http_ok(f"{url}/healthz")):
        ready = lambda: HTTP.get(f"{url}/api/v1/bags/scenario").json()["status"] == "ready"  # noqa: E731
        wait_until(ready, timeout_s=60, what="ingest")
        yield url


@pytest.mark.parametrize(
    ("method", "path"),
    [
        ("GET", "/api/v1/bags/scenario/download"),
        ("GET", "/api/v1/bags"),
        ("GET", "/api/v1/bags/scenario"),
        ("DELETE", "/api/v1/bags/scenario"),
        ("POST", "/mcp"),
    ],
)
def test_a_foreign_host_header_is_refused_on_every_route(loopback: str, method: str, path: str) -> None:
    body = json.dumps(INITIALIZE) if path == "/mcp" else None
    headers = {**MCP_HEADERS, "Host": "attacker.example:80"}
    answer = httpx.request(method, f"{loopback}{path}", headers=headers, content=body)
    assert answer.status_code == 421
    assert answer.json()["error"]["code"] == "misdirected_request"
    assert "scenario" not in answer.text


def test_the_same_routes_answer_by_their_loopback_name(loopback: str) -> None:
    assert httpx.get(f"{loopback}/api/v1/bags/scenario/download").content.startswith(b"#ROSBAG V2.0")
    port = loopback.rsplit(":", 1)[1]
    assert httpx.get(f"{loopback}/api/v1/bags", headers={"Host": f"localhost:{port}"}).status_code == 200
    mcp = httpx.post(f"{loopback}/mcp", headers=MCP_HEADERS, content=json.dumps(INITIALIZE))
    assert mcp.status_code == 200


def test_a_page_of_another_site_cannot_read_through_a_loopback_name(loopback: str) -> None:
    answer = httpx.get(f"{loopback}/api/v1/bags/scenario/download", headers={"Origin": "http://attacker.example"})
    assert answer.status_code == 403
    assert answer.json()["error"]["code"] == "forbidden_origin"


@pytest.mark.parametrize("how", ["flag", "environment"])
def test_a_server_on_every_address_answers_to_the_names_it_is_given(folder: Path, tmp_path: Path, how: str) -> None:
    port = free_port()
    extra = ["--allowed-host", "bags.lab"] if how == "flag" else []
    env = {"BAGMCP_ALLOWED_HOSTS": "bags.lab"} if how == "environment" else {}
    command = _serve(folder, port, tmp_path / "data", "--host", "0.0.0.0", "--token", "t0k", *extra)
    url = f"http://127.0.0.1:{port}"
    with service("serve-any", command, env=env, log_dir=tmp_path, ready=http_ok(f"{url}/healthz")):
        token = {"Authorization": "Bearer t0k"}
        named = httpx.get(f"{url}/api/v1/bags", headers={**token, "Host": f"bags.lab:{port}"})
        assert named.status_code == 200
        assert [b["name"] for b in named.json()["bags"]] == ["scenario"]
        mcp = httpx.post(
            f"{url}/mcp", headers={**MCP_HEADERS, **token, "Host": f"bags.lab:{port}"}, content=json.dumps(INITIALIZE)
        )
        assert mcp.status_code == 200
        assert httpx.get(f"{url}/api/v1/bags", headers={"Host": f"bags.lab:{port}"}).status_code == 401
        other = httpx.get(f"{url}/api/v1/bags", headers={**token, "Host": f"0.0.0.0:{port}"})
        assert other.status_code == 421
