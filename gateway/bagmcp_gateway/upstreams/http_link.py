"""A lean HTTP/1.1 client for the gateway's posts to one upstream over plain ``http://``: kept-alive
connections on asyncio streams, each request written at once, answers parsed with h11.

Why not httpx2: per request it costs the gateway about 1.3 ms of CPU (its models, header normalisation,
connection-pool locks and stream wrappers), against about 0.2 ms here, measured on a tools/call to the
bag-store; that was most of the gateway's added latency. The upstreams are the team's own services on its
network (TLS and proxies are for third-party servers, which go through the SDK client).

A connection found closed, or idle longer than the servers keep one open, is not reused. A reused
connection that ends before any byte of the answer is retried once on a new one (the server closed it as
idle, so it never saw the request). A request that is cancelled or fails closes its connection.
"""

from __future__ import annotations

import asyncio
import time
from collections.abc import AsyncIterator, Mapping
from contextlib import asynccontextmanager
from dataclasses import dataclass, field
from urllib.parse import urlsplit

import h11

IDLE_S = 4.0  # below uvicorn's keep-alive (5 s): never send on a connection the server is about to close
MAX_IDLE = 64
READ_BYTES = 65536


class LinkClosedError(ConnectionError):
    """The upstream closed the connection before answering."""


@dataclass
class _Connection:
    reader: asyncio.StreamReader
    writer: asyncio.StreamWriter
    http: h11.Connection = field(default_factory=lambda: h11.Connection(h11.CLIENT))
    idle_since: float = 0.0

    def usable(self) -> bool:
        fresh = time.monotonic() - self.idle_since < IDLE_S
        return fresh and not self.reader.at_eof() and not self.writer.is_closing()

    def close(self) -> None:
        self.writer.close()


@dataclass
class Answer:
    """An upstream's answer: status and content type first, then the body as it arrives."""

    status: int
    content_type: str
    _connection: _Connection

    async def chunks(self) -> AsyncIterator[bytes]:
        while True:
            event = self._connection.http.next_event()
            if event is h11.NEED_DATA:
                self._connection.http.receive_data(await self._connection.reader.read(READ_BYTES))
            elif isinstance(event, h11.Data):
                yield bytes(event.data)
            elif isinstance(event, h11.EndOfMessage):
                return
            elif isinstance(event, h11.ConnectionClosed):
                raise LinkClosedError("the upstream closed the connection in the middle of its answer")

    async def read(self) -> bytes:
        return b"".join([chunk async for chunk in self.chunks()])


class HttpLink:
    """POSTs to ``url`` (``http://`` only) with ``headers`` on every request; ``close`` when done."""

    def __init__(self, url: str, *, headers: Mapping[str, str], connect_timeout_s: float) -> None:
        parts = urlsplit(url)
        if parts.scheme != "http" or parts.hostname is None:
            raise ValueError(f"HttpLink serves http:// URLs only, not {url!r}")
        self._host, self._port = parts.hostname, parts.port or 80
        self._target = (parts.path or "/") + (f"?{parts.query}" if parts.query else "")
        authority = f"{self._host}:{self._port}"
        self._headers = [("host", authority), *headers.items()]
        self._connect_timeout_s = connect_timeout_s
        self._idle: list[_Connection] = []

    async def close(self) -> None:
        while self._idle:
            self._idle.pop().close()

    async def _open(self) -> _Connection:
        async with asyncio.timeout(self._connect_timeout_s):
            reader, writer = await asyncio.open_connection(self._host, self._port, limit=READ_BYTES)
        return _Connection(reader, writer)

    def _reused(self) -> _Connection | None:
        while self._idle:
            connection = self._idle.pop()
            if connection.usable():
                return connection
            connection.close()
        return None

    async def _send(self, connection: _Connection, body: bytes, headers: Mapping[str, str]) -> h11.Response:
        """Write the request, read up to the answer's status and headers. LinkClosedError when the connection
        ends before the first byte of the answer."""
        sent = [*self._headers, *headers.items(), ("content-length", str(len(body)))]
        http = connection.http
        request = [http.send(h11.Request(method="POST", target=self._target, headers=sent))]
        request += [http.send(h11.Data(data=body)), http.send(h11.EndOfMessage())]
        try:
            connection.writer.write(b"".join(part or b"" for part in request))
            await connection.writer.drain()
            data = await connection.reader.read(READ_BYTES)
        except ConnectionError as err:
            raise LinkClosedError(f"the connection to the upstream broke before its answer ({err})") from err
        if not data:
            raise LinkClosedError("the upstream closed the connection without answering")
        http.receive_data(data)
        while True:
            event = http.next_event()
            if event is h11.NEED_DATA:
                http.receive_data(await connection.reader.read(READ_BYTES))
            elif isinstance(event, h11.Response):
                return event
            elif isinstance(event, h11.ConnectionClosed):
                raise ConnectionError("the upstream closed the connection in the middle of its answer")

    async def _answered(self, body: bytes, headers: Mapping[str, str]) -> tuple[_Connection, h11.Response]:
        reused = self._reused()
        if reused is not None:
            try:
                return reused, await self._send(reused, body, headers)
            except LinkClosedError:  # closed as idle before it saw the request: once more, on a new one
                reused.close()
            except BaseException:
                reused.close()
                raise
        fresh = await self._open()
        try:
            return fresh, await self._send(fresh, body, headers)
        except BaseException:
            fresh.close()
            raise

    @asynccontextmanager
    async def post(self, body: bytes, headers: Mapping[str, str]) -> AsyncIterator[Answer]:
        """The answer to POSTing ``body``; read it inside the block. The connection goes back to the pool
        when the answer was read to its end, and is closed otherwise."""
        connection, response = await self._answered(body, headers)
        kind = next((v for k, v in response.headers if k == b"content-type"), b"").decode("latin-1")
        done = False
        try:
            yield Answer(response.status_code, kind.partition(";")[0].strip().lower(), connection)
            http = connection.http
            done = http.our_state is h11.DONE and http.their_state is h11.DONE
        finally:
            if done and len(self._idle) < MAX_IDLE:
                connection.http.start_next_cycle()
                connection.idle_since = time.monotonic()
                self._idle.append(connection)
            else:
                connection.close()
