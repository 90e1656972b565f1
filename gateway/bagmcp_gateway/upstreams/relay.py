"""A request to an upstream that speaks the stateless 2026-07-28 protocol, sent as one JSON-RPC exchange over
HTTP and its result handed back as decoded JSON, not as SDK models.

The gateway relays a result unchanged, so parsing it into models only to dump it again for the caller is
pure cost (most of the gateway's own time per cheap call). The exchange is the protocol's: the request
envelope in ``_meta`` and the routing headers, an answer as ``application/json`` or as an event stream
whose ``notifications/progress`` are handed to ``progress`` until the response arrives. Closing the stream
(a cancelled caller) is the protocol's cancellation.
"""

from __future__ import annotations

import codecs
import itertools
import json
from collections.abc import AsyncIterator, Awaitable, Callable, Mapping
from typing import Any

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

from bagmcp_gateway.upstreams.http_link import HttpLink

Progress = Callable[[float, float | None, str | None], Awaitable[None]]
WireResult = dict[str, Any]  # a JSON-RPC result as it travels: what the upstream sent, or what the gateway makes
PROTOCOL_VERSION = MODERN_PROTOCOL_VERSIONS[-1]
CLIENT_INFO = {"name": "bagmcp-gateway", "version": "1"}


def _decoded(body: bytes | str, *, upstream: str) -> WireResult:
    try:
        message = json.loads(body)
    except ValueError as err:
        raise MCPError(INTERNAL_ERROR, f"the {upstream} service answered with invalid JSON") from err
    if not isinstance(message, dict):
        raise MCPError(INTERNAL_ERROR, f"the {upstream} service answered with something not JSON-RPC")
    return message


def _result(message: Mapping[str, Any], *, upstream: str) -> WireResult:
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


async def _events(chunks: AsyncIterator[bytes]) -> AsyncIterator[str]:
    """The ``data`` of each server-sent event in a stream (its lines joined), as they arrive."""
    pending, data, text = "", list[str](), codecs.getincrementaldecoder("utf-8")()
    async for chunk in chunks:
        pending += text.decode(chunk)
        *lines, pending = pending.split("\n")
        for line in (raw.rstrip("\r") for raw in lines):
            if line.startswith("data:"):
                data.append(line[5:].removeprefix(" "))
            elif not line and data:
                yield "\n".join(data)
                data = []


class JsonRpcRelay:
    """One upstream's ``http://`` endpoint (``url``), over kept-alive connections; ``close`` when done."""

    def __init__(self, name: str, url: str, *, headers: Mapping[str, str], timeout_s: float) -> None:
        self._name = name
        self._ids = itertools.count(1)
        self._link = HttpLink(url, headers=headers, connect_timeout_s=timeout_s)

    async def close(self) -> None:
        await self._link.close()

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
    ) -> WireResult:
        """The result of ``method`` with ``params`` (``meta`` added to the envelope, ``headers`` to the routing
        headers); MCPError for an error answer; OSError when the upstream cannot be reached."""
        rid, body, sent = self._request(method, params, meta)
        sent.update(headers or {})
        async with self._link.post(body, sent) as answer:
            if answer.content_type == "text/event-stream":
                return await self._streamed(_events(answer.chunks()), rid, progress)
            message = _decoded(await answer.read(), upstream=self._name)
            if "error" not in message and answer.status != 200:
                raise MCPError(INTERNAL_ERROR, f"the {self._name} service answered HTTP {answer.status}")
            return _result(message, upstream=self._name)

    async def _streamed(self, events: AsyncIterator[str], rid: int, progress: Progress | None) -> WireResult:
        async for data in events:
            message = _decoded(data, upstream=self._name)
            if message.get("id") == rid:
                return _result(message, upstream=self._name)
            if progress is not None and message.get("method") == "notifications/progress":
                await _progressed(message.get("params"), rid, progress)
        raise MCPError(INTERNAL_ERROR, f"the {self._name} service closed its answer before the result")
