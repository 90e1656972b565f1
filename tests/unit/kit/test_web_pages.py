"""Pages and static files are served with the strict Content-Security-Policy and never list directories
or leave the static folder; the gateway's console route answers at /."""

from __future__ import annotations

from fastapi import FastAPI
from fastapi.testclient import TestClient

from bagmcp_gateway.console import install_console
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
