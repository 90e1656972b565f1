"""A loopback TCP proxy between the services and the S3 server: it adds a fixed delay to every request and
counts the bytes each way, so the benchmark can time cold reads as if S3 were across a network and see
every byte any process fetched (the services' /metrics count only the block cache's ranges; whole copies,
index files and the workers' reads pass here too).

A request is what a client sends after the server last answered on that connection: the first bytes of
each such turn wait ``delay_s`` before they go on, the rest of the turn (a request body) does not, and
answers pass at once. One delay per HTTP request on a kept-alive connection, none per packet.
"""

from __future__ import annotations

import asyncio
import re
import threading
from collections import deque
from collections.abc import Iterator
from contextlib import contextmanager, suppress
from dataclasses import dataclass

CHUNK = 256 * 1024
RECENT = 1000
_RANGE = re.compile(rb"\r\nrange: *([^\r]*)", re.IGNORECASE)
ANSWER_AFTER_EOF_S = 60.0


def request_line(head: bytes) -> str:
    """``METHOD /path [bytes=a-b]`` of a request's first bytes (its query string left out)."""
    first = head.split(b"\r\n", 1)[0].decode("latin-1")
    method, _, rest = first.partition(" ")
    path = rest.split(" ", 1)[0].split("?", 1)[0]
    found = _RANGE.search(head)
    return f"{method} {path}" + (f" {found.group(1).decode('latin-1')}" if found else "")


@dataclass(frozen=True)
class ProxyCounts:
    """Since the proxy started: requests delayed (turns), bytes sent to S3 and bytes S3 answered."""

    requests: int = 0
    sent_bytes: int = 0
    answered_bytes: int = 0

    def __sub__(self, other: ProxyCounts) -> ProxyCounts:
        return ProxyCounts(
            self.requests - other.requests,
            self.sent_bytes - other.sent_bytes,
            self.answered_bytes - other.answered_bytes,
        )

    def __add__(self, other: ProxyCounts) -> ProxyCounts:
        return ProxyCounts(
            self.requests + other.requests,
            self.sent_bytes + other.sent_bytes,
            self.answered_bytes + other.answered_bytes,
        )


class DelayProxy:
    """Listens on a free loopback port and forwards each connection to ``target`` (``host:port``).
    ``delay_s`` may be changed while it runs; it applies to requests that start afterwards."""

    def __init__(self, target: str, *, delay_s: float = 0.0) -> None:
        host, _, port = target.rpartition(":")
        self._target = (host, int(port))
        self.delay_s = delay_s
        self.port = 0
        self._counts = [0, 0, 0]  # requests, sent, answered: added on the proxy's loop only
        self.recent: deque[str] = deque(maxlen=RECENT)  # the latest requests: method, path and Range
        self._loop = asyncio.new_event_loop()
        self._started = threading.Event()
        self._stopping = asyncio.Event()  # bound to the proxy's loop on first use (Python 3.10+)
        self._thread = threading.Thread(target=self._run, name="delay-proxy", daemon=True)

    @property
    def endpoint(self) -> str:
        return f"127.0.0.1:{self.port}"

    def counts(self) -> ProxyCounts:
        requests, sent, answered = self._counts
        return ProxyCounts(requests, sent, answered)

    def start(self) -> None:
        self._thread.start()
        if not self._started.wait(10) or not self.port:
            raise RuntimeError("the delay proxy did not start listening within 10 s")

    def stop(self) -> None:
        """Close the listener and every open connection, then end the proxy's thread."""
        self._loop.call_soon_threadsafe(self._stopping.set)
        self._thread.join(10)

    def _run(self) -> None:
        asyncio.set_event_loop(self._loop)
        try:
            self._loop.run_until_complete(self._serve())
        finally:
            self._loop.close()

    async def _serve(self) -> None:
        server = await asyncio.start_server(self._connection, "127.0.0.1", 0)
        self.port = int(server.sockets[0].getsockname()[1])
        self._started.set()
        async with server:
            await self._stopping.wait()
        others = [t for t in asyncio.all_tasks() if t is not asyncio.current_task()]
        for task in others:
            task.cancel()
        await asyncio.gather(*others, return_exceptions=True)

    async def _connection(self, client_in: asyncio.StreamReader, client_out: asyncio.StreamWriter) -> None:
        try:
            with suppress(asyncio.CancelledError):  # cancelled when the proxy stops: ends quietly
                await self._relay(client_in, client_out)
        finally:
            client_out.close()  # on a stop too: a writer left open warns when it is collected

    async def _relay(self, client_in: asyncio.StreamReader, client_out: asyncio.StreamWriter) -> None:
        try:
            server_in, server_out = await asyncio.open_connection(*self._target)
        except OSError:
            return
        turn = [True]  # the client's next bytes start a request
        upward = asyncio.create_task(self._requests(client_in, server_out, turn))
        downward = asyncio.create_task(self._answers(server_in, client_out, turn))
        try:
            done, _ = await asyncio.wait((upward, downward), return_when=asyncio.FIRST_COMPLETED)
            if upward in done and not downward.done():  # the client is done sending: let the answer finish
                await asyncio.wait((downward,), timeout=ANSWER_AFTER_EOF_S)
        finally:
            for task in (upward, downward):
                task.cancel()
            server_out.close()
        for writer in (client_out, server_out):
            writer.close()
            with suppress(OSError, asyncio.CancelledError):
                await writer.wait_closed()

    async def _requests(self, source: asyncio.StreamReader, sink: asyncio.StreamWriter, turn: list[bool]) -> None:
        with suppress(OSError):
            await self._pass_requests(source, sink, turn)

    async def _pass_requests(self, source: asyncio.StreamReader, sink: asyncio.StreamWriter, turn: list[bool]) -> None:
        while data := await source.read(CHUNK):
            if turn[0]:
                turn[0] = False
                self._counts[0] += 1
                self.recent.append(request_line(data))
                if self.delay_s > 0:
                    await asyncio.sleep(self.delay_s)
            self._counts[1] += len(data)
            sink.write(data)
            await sink.drain()
        sink.write_eof()

    async def _answers(self, source: asyncio.StreamReader, sink: asyncio.StreamWriter, turn: list[bool]) -> None:
        with suppress(OSError):
            while data := await source.read(CHUNK):
                turn[0] = True
                self._counts[2] += len(data)
                sink.write(data)
                await sink.drain()


@contextmanager
def delay_proxy(target: str, *, delay_s: float = 0.0) -> Iterator[DelayProxy]:
    """A running proxy in front of ``target``, stopped on exit."""
    proxy = DelayProxy(target, delay_s=delay_s)
    proxy.start()
    try:
        yield proxy
    finally:
        proxy.stop()
