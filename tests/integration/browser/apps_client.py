"""An MCP client that says it renders MCP Apps, as a host such as Claude Desktop does: plain JSON-RPC on the
2026-07-28 protocol over HTTP (one POST a request), so the tests see the wire answers a host sees."""

from __future__ import annotations

import json
from typing import Any

import httpx

PROTOCOL = "2026-07-28"
APPS = {"extensions": {"io.modelcontextprotocol/ui": {"mimeTypes": ["text/html;profile=mcp-app"]}}}
NAME_OF = {"tools/call": "name", "resources/read": "uri"}


def _answer(response: httpx.Response) -> dict[str, Any]:
    if "text/event-stream" not in response.headers.get("content-type", ""):
        return dict(response.json())
    events = [line[5:].strip() for line in response.text.splitlines() if line.startswith("data:")]
    answers = [json.loads(e) for e in events if e and '"id"' in e]
    return dict(answers[-1])


def rpc(url: str, token: str, method: str, params: dict[str, Any], *, apps: bool = True) -> dict[str, Any]:
    """The result of one request to ``url``/mcp; ``apps`` False asks as a client without MCP Apps."""
    meta = {
        "io.modelcontextprotocol/protocolVersion": PROTOCOL,
        "io.modelcontextprotocol/clientInfo": {"name": "bagmcp-browser-tests", "version": "1"},
        "io.modelcontextprotocol/clientCapabilities": APPS if apps else {},
    }
    headers = {
        "Authorization": f"Bearer {token}",
        "Accept": "application/json, text/event-stream",
        "MCP-Protocol-Version": PROTOCOL,
        "Mcp-Method": method,
    }
    if method in NAME_OF:
        headers["Mcp-Name"] = str(params[NAME_OF[method]])
    body = {"jsonrpc": "2.0", "id": 1, "method": method, "params": {**params, "_meta": meta}}
    response = httpx.post(f"{url}/mcp", json=body, headers=headers, timeout=180)
    response.raise_for_status()
    message = _answer(response)
    assert "error" not in message, message
    return dict(message["result"])


def call_tool(url: str, token: str, name: str, arguments: dict[str, Any], *, apps: bool = True) -> dict[str, Any]:
    result = rpc(url, token, "tools/call", {"name": name, "arguments": arguments}, apps=apps)
    assert not result.get("isError"), result
    return result
