"""The gateway's lean HTTP/1.1 link to its upstreams, against a real socket server on loopback that answers
as told: connections are kept alive and reused, one the server dropped without answering is retried once
on a new connection, an event stream is read as it arrives (events split across chunks, UTF-8 split
mid-character), and an answer abandoned half-way closes its connection instead of reusing it."""

from __future__ import annotations

import asyncio
import json
from collections.abc import AsyncIterator, Callable
from contextlib import asynccontextmanager
from dataclasses import dataclass, field

import anyio
import pytest

from bagmcp_gateway.upstreams.http_link import HttpLink
from bagmcp_gateway.upstreams.relay import JsonRpcRelay

pytestmark = pytest.mark.anyio
Reply = Callable[[int, bytes], list[bytes] | None]  # (request number, body) -> chunks to send, None: hang up


@dataclass
class _Server:
    """Answers each request with what ``reply`` gives (sent chunk by chunk); counts connections."""

    reply: Reply
    connections: int = 0
    requests: list[bytes] = field(default_factory=list)

    async def _serve(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        self.connections += 1
        try:
            while head := await reader.readuntil(b"\r\n\r\n"):
                length = next(
                    int(v)
                    for k, _, v in (h.partition(b":") for h in head.split(b"\r\n"))
                    if k.lower() == b"content-length"
                )
                body = await reader.readexactly(length)
                self.requests.append(body)
                chunks = self.reply(len(self.requests), body)
                if chunks is None:
                    return
                for chunk in chunks:
                    writer.write(chunk)
                    await writer.drain()
                    await asyncio.sleep(0.01)
        except (asyncio.IncompleteReadError, ConnectionError):
            return
        finally:
            writer.close()


@asynccontextmanager
async def _serving(reply: Reply) -> AsyncIterator[tuple[_Server, str]]:
    server = _Server(reply)
    listening = await asyncio.start_server(server._serve, "127.0.0.1", 0)
    port = listening.sockets[0].getsockname()[1]
    async with listening:
        yield server, f"http://127.0.0.1:{port}/mcp"


def _json(body: bytes) -> list[bytes]:
    return [b"HTTP/1.1 200 OK\r\ncontent-type: application/json\r\ncontent-length: %d\r\n\r\n" % len(body), body]


def _echo(number: int, body: bytes) -> list[bytes]:
    request = json.loads(body)
    return _json(json.dumps({"jsonrpc": "2.0", "id": request["id"], "result": {"n": number}}).encode())


async def test_connections_are_kept_alive_and_a_dropped_one_is_retried_once_on_a_new_connection() -> None:
    def drop_the_second(number: int, body: bytes) -> list[bytes] | None:
        return None if number == 2 else _echo(number, body)

    async with _serving(drop_the_second) as (server, url):
        relay = JsonRpcRelay("echo", url, headers={}, timeout_s=5)
        try:
            first = await relay.request("tools/call", {"name": "a", "arguments": {}}, meta={})
            again = await relay.request("tools/call", {"name": "a", "arguments": {}}, meta={})
        finally:
            await relay.close()
    assert (first, again) == ({"n": 1}, {"n": 3})  # the second request reached the server twice
    assert server.connections == 2
    assert server.requests[1] == server.requests[2]


async def test_an_event_stream_is_read_as_it_arrives_with_progress_before_the_result() -> None:
    def stream(number: int, body: bytes) -> list[bytes]:
        rid = json.loads(body)["id"]
        note = {"jsonrpc": "2.0", "method": "notifications/progress"}
        events = [
            {**note, "params": {"progressToken": rid, "progress": 1, "total": 2, "message": "étape 1"}},
            {**note, "params": {"progressToken": rid + 1000, "progress": 9}},  # another request's: not ours
            {"jsonrpc": "2.0", "id": rid, "result": {"text": "fini ✓"}},
        ]
        wire = "".join(f"event: message\r\ndata: {json.dumps(e, ensure_ascii=False)}\r\n\r\n" for e in events).encode()
        cut = wire.index("é".encode()) + 1  # mid-character
        head = b"HTTP/1.1 200 OK\r\ncontent-type: text/event-stream\r\ntransfer-encoding: chunked\r\n\r\n"
        return [head, *(b"%x\r\n%s\r\n" % (len(part), part) for part in (wire[:cut], wire[cut:])), b"0\r\n\r\n"]

    seen: list[tuple[float, float | None, str | None]] = []

    async def progress(done: float, total: float | None, message: str | None) -> None:
        seen.append((done, total, message))

    async with _serving(stream) as (_server, url):
        relay = JsonRpcRelay("stream", url, headers={}, timeout_s=5)
        try:
            result = await relay.request("tools/call", {"name": "a"}, meta={}, progress=progress)
        finally:
            await relay.close()
    assert result == {"text": "fini ✓"}
    assert seen == [(1.0, 2.0, "étape 1")]


async def test_an_answer_abandoned_half_way_closes_its_connection() -> None:
    def slow(number: int, body: bytes) -> list[bytes]:
        head = b"HTTP/1.1 200 OK\r\ncontent-type: application/json\r\ncontent-length: 1000\r\n\r\n"
        return [head, b"{" + b" " * 10] + [b" "] * 500

    async with _serving(slow) as (server, url):
        link = HttpLink(url, headers={}, connect_timeout_s=5)
        with anyio.move_on_after(0.2):
            async with link.post(b"{}", {"content-type": "application/json"}) as answer:
                assert answer.status == 200
                await answer.read()
        async with link.post(b"{}", {"content-type": "application/json"}) as answer:
            assert answer.status == 200
        await link.close()
    assert server.connections == 2  # the abandoned connection was not reused
