"""A request to an upstream that speaks the stateless 2026-07-28 protocol, sent as one JSON-RPC exchange over
HTTP and its result handed back as decoded JSON, not as SDK models.

The gateway relays a result unchanged, so parsing it into models only to dump it again for the caller is
pure cost (most of the gateway's own time per cheap call). The exchange is the protocol's: the request
envelope in ``_meta`` and the routing headers, an answer as ``application/json`` or as an event stream
whose ``notifications/progress`` are handed to ``progress`` until the response arrives. Closing the stream
(a cancelled caller) is the protocol's cancellation.
"""

from __future__ import annotations

import itertools
import json
from collections.abc import Awaitable, Callable, Mapping
from typing import Any

import httpx2
from mcp import MCPError
from mcp.shared.inbound import (
    MCP_METHOD_HEADER,
    MCP_NAME_HEADER,
    MCP_PROTOCOL_VERSION_HEADER,
    NAME_BEARING_METHODS,
    encode_header_value,
)
from mcp.types import CLIENT_CAPABILITIES_META_KEY, CLIENT_INFO_META_KEY, INTERNAL_ERROR, PROTOCOL_VERSION_META_KEY
from mcp_types.version import MODERN_PROTOCOL_VERSIONS

Progress = Callable[[float, float | None, str | None], Awaitable[None]]
PROTOCOL_VERSION = MODERN_PROTOCOL_VERSIONS[-1]
CLIENT_INFO = {"name": "bagmcp-gateway", "version": "1"}


def _decoded(body: bytes | str, *, upstream: str) -> dict[str, Any]:
    try:
        message = json.loads(body)
    except ValueError as err:
        raise MCPError(INTERNAL_ERROR, f"the {upstream} service answered with invalid JSON") from err
    if not isinstance(message, dict):
        raise MCPError(INTERNAL_ERROR, f"the {upstream} service answered with something not JSON-RPC")
    return message


def _result(message: Mapping[str, Any], *, upstream: str) -> dict[str, Any]:
    """The result of a JSON-RPC response, or its error raised as MCPError."""
    error = message.get("error")
    if isinstance(error, dict):
        code = error.get("code")
        raise MCPError(code if isinstance(code, int) else INTERNAL_ERROR, str(error.get("message")), error.get("data"))
    result = message.get("result")
    if not isinstance(result, dict):
        raise MCPError(INTERNAL_ERROR, f"the {upstream} service answered without a result")
    return result


async def _progressed(params: object, token: int, progress: Progress) -> None:
    if not isinstance(params, dict) or params.get("progressToken") != token:
        return
    done, total, message = params.get("progress"), params.get("total"), params.get("message")
    if isinstance(done, int | float):
        total_n = float(total) if isinstance(total, int | float) else None
        await progress(float(done), total_n, message if isinstance(message, str) else None)


class JsonRpcRelay:
    """One upstream's HTTP endpoint (``url``), with a pooled HTTP client; ``close`` when done."""

    def __init__(self, name: str, url: str, *, headers: Mapping[str, str], timeout_s: float) -> None:
        self._name = name
        self._url = url
        self._ids = itertools.count(1)
        self._http = httpx2.AsyncClient(headers=dict(headers), timeout=httpx2.Timeout(timeout_s, read=None))

    async def close(self) -> None:
        await self._http.aclose()

    def _request(
        self, method: str, params: Mapping[str, Any], meta: Mapping[str, Any]
    ) -> tuple[int, bytes, dict[str, str]]:
        rid = next(self._ids)
        envelope = {
            **meta,
            PROTOCOL_VERSION_META_KEY: PROTOCOL_VERSION,
            CLIENT_INFO_META_KEY: CLIENT_INFO,
            CLIENT_CAPABILITIES_META_KEY: {},
            "progressToken": rid,
        }
        body = {"jsonrpc": "2.0", "id": rid, "method": method, "params": {**params, "_meta": envelope}}
        headers = {
            "content-type": "application/json",
            "accept": "application/json, text/event-stream",
            MCP_PROTOCOL_VERSION_HEADER: PROTOCOL_VERSION,
            MCP_METHOD_HEADER: method,
        }
        if (key := NAME_BEARING_METHODS.get(method)) is not None and isinstance(name := params.get(key), str):
            headers[MCP_NAME_HEADER] = encode_header_value(name)
        return rid, json.dumps(body, separators=(",", ":")).encode(), headers

    async def request(
        self,
        method: str,
        params: Mapping[str, Any],
        *,
        meta: Mapping[str, Any],
        headers: Mapping[str, str] | None = None,
        progress: Progress | None = None,
    ) -> dict[str, Any]:
        """The result of ``method`` with ``params`` (``meta`` added to the envelope, ``headers`` to the routing
        headers); MCPError for an error answer; httpx2 errors when the upstream cannot be reached."""
        rid, body, sent = self._request(method, params, meta)
        sent.update(headers or {})
        async with self._http.stream("POST", self._url, content=body, headers=sent) as response:
            kind = response.headers.get("content-type", "").partition(";")[0].strip().lower()
            if kind == "text/event-stream":
                return await self._streamed(response, rid, progress)
            message = _decoded(await response.aread(), upstream=self._name)
            if "error" not in message and response.status_code != 200:
                raise MCPError(INTERNAL_ERROR, f"the {self._name} service answered HTTP {response.status_code}")
            return _result(message, upstream=self._name)

    async def _streamed(self, response: httpx2.Response, rid: int, progress: Progress | None) -> dict[str, Any]:
        async for event in httpx2.EventSource(response):
            if not event.data:
                continue
            message = _decoded(event.data, upstream=self._name)
            if message.get("id") == rid:
                return _result(message, upstream=self._name)
            if progress is not None and message.get("method") == "notifications/progress":
                await _progressed(message.get("params"), rid, progress)
        raise MCPError(INTERNAL_ERROR, f"the {self._name} service closed its answer before the result")
