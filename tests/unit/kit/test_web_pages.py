"""Pages and static files are served with the strict Content-Security-Policy and never list directories
or leave the static folder; the gateway's console route answers at /."""

from __future__ import annotations

import contextlib
from collections.abc import AsyncIterator

from fastapi import FastAPI, Request
from fastapi.testclient import TestClient

from bagmcp_gateway.rest_front.console import install_console
from bagmcp_kit.service_app import new_app
from bagmcp_kit.web.pages import CSP


def _client() -> TestClient:
    app = FastAPI()
    install_console(app, token_required=True)
    return TestClient(app)


def test_the_console_page_and_its_files_carry_the_csp() -> None:
    client = _client()
    page = client.get("/")
    assert page.status_code == 200
    assert page.headers["content-security-policy"] == CSP
    assert "'unsafe-inline'" not in CSP
    assert "frame-ancestors 'none'" in CSP
    assert '<main id="main"' in page.text
    script = client.get("/static/views/dom.js")
    assert script.status_code == 200
    assert script.headers["content-security-policy"] == CSP
    assert script.headers["x-content-type-options"] == "nosniff"
    assert "textContent" in script.text or "createTextNode" in script.text
    assert client.get("/console.json").json() == {"token_required": True}


def test_static_files_stay_inside_their_folder_and_list_nothing() -> None:
    client = _client()
    assert client.get("/static/").status_code == 404
    assert client.get("/static/views/").status_code == 404
    assert client.get("/static/../assets.py").status_code == 404
    assert client.get("/static/%2e%2e/assets.py").status_code == 404


@contextlib.asynccontextmanager
async def _nothing(_app: FastAPI) -> AsyncIterator[None]:
    yield


async def _anyone(_request: Request) -> None:
    return None


def test_pages_answer_only_to_the_host_names_the_api_answers_to() -> None:
    app = new_app(title="t", lifespan=_nothing, routers=[], guard=_anyone, allowed_hosts=["testserver"])
    install_console(app, token_required=True)
    client = TestClient(app)
    assert client.get("/").status_code == 200
    assert client.get("/", headers={"Host": "bags.attacker.example"}).status_code == 421
    assert client.get("/static/views/dom.js", headers={"Host": "bags.attacker.example"}).status_code == 421
    assert client.get("/console.json", headers={"Origin": "http://attacker.example"}).status_code == 403
