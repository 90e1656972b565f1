"""Slow and abandoned uploads through the gateway (a handful of raw connections, a 2 s idle setting): an upload
that sends nothing for the idle time ends with 408 and a sentence, a token holds at most its number of uploads
at once (429 with a sentence) while other tokens upload, and a client that goes away mid-upload costs one log
line, no traceback. `bagmcp serve` (the embedded gateway, same settings) refuses every upload at once, before
reading its body, and closes its connection, so a slow one holds nothing there. Before, 1,500 uploads at 1 byte
per 2 s starved the gateway and each aborted one logged two tracebacks."""

from __future__ import annotations

import http.client
import json
import socket
import threading
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import httpx
import pytest

from bagmcp_gateway.access.upload_limits import UPLOAD_PATH
from tests.fixtures.bagfactory import write_chatter_bag
from tests.fixtures.processes import BIN, http_ok, service, wait_until
from tests.fixtures.servers import free_port
from tests.integration.stack import OTHER_TOKEN, TOKEN, Stack, bagmcp, run_gateway

IDLE_S = 2
PER_TOKEN = 2
SETTINGS = {"BAGMCP_UPLOAD_IDLE_S": str(IDLE_S), "BAGMCP_UPLOADS_PER_TOKEN": str(PER_TOKEN)}


@pytest.fixture(scope="module")
def gateway(stack: Stack) -> Iterator[str]:
    port = free_port()
    with run_gateway(stack, "gateway-slow-uploads", port, SETTINGS):
        yield f"http://127.0.0.1:{port}"


@pytest.fixture(scope="module")
def served(tmp_path_factory: pytest.TempPathFactory) -> Iterator[str]:
    """`bagmcp serve --token TOKEN` over an empty folder, with the same upload settings as the gateway."""
    folder, data, logs = (tmp_path_factory.mktemp(n) for n in ("slow-serve-bags", "slow-serve-data", "slow-serve-logs"))
    port = free_port()
    url = f"http://127.0.0.1:{port}"
    command = [str(BIN / "bagmcp"), "serve", "--bags", str(folder), "--port", str(port), "--data", str(data)]
    with service(
        "serve-slow-uploads", [*command, "--token", TOKEN], env=SETTINGS, log_dir=logs, ready=http_ok(f"{url}/healthz")
    ):
        yield url


class SlowUpload:
    """One raw upload connection: the request head, then a byte every ``every_s`` seconds (never, with None)."""

    def __init__(self, url: str, token: str, *, every_s: float | None = None) -> None:
        port = int(url.rsplit(":", 1)[1])
        self.sock = socket.create_connection(("127.0.0.1", port), timeout=20)
        head = (
            f"POST /api/v1/bags?filename=slow.mcap HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\n"
            f"Authorization: Bearer {token}\r\nContent-Type: application/octet-stream\r\n"
            f"Content-Length: {1 << 20}\r\n\r\n"
        )
        self.sock.sendall(head.encode() + b"\x89")
        self._stop = threading.Event()
        if every_s is not None:
            threading.Thread(target=self._trickle, args=(every_s,), daemon=True).start()

    def _trickle(self, every_s: float) -> None:
        while not self._stop.wait(every_s):
            try:
                self.sock.sendall(b"M")
            except OSError:
                return

    def answer(self) -> tuple[int, dict[str, Any]]:
        response = http.client.HTTPResponse(self.sock)
        response.begin()
        return response.status, json.loads(response.read())

    def close(self) -> None:
        self._stop.set()
        self.sock.close()


def _log_after(path: Path, offset: int) -> str:
    return path.read_bytes()[offset:].decode(errors="replace")


def test_an_upload_that_stalls_ends_with_408_and_a_sentence(stack: Stack, gateway: str) -> None:
    began = time.monotonic()
    upload = SlowUpload(gateway, TOKEN)
    try:
        status, body = upload.answer()
    finally:
        upload.close()
    assert status == 408
    assert body["error"]["code"] == "upload_stalled"
    assert body["error"]["message"].startswith(f"the upload sent nothing for {IDLE_S} s")
    assert IDLE_S <= time.monotonic() - began < IDLE_S + 5
    wait_until(lambda: stack.upload_leftovers() == [], timeout_s=10, what="the bag-store to drop the partial body")


def test_a_token_holds_at_most_its_uploads_at_once_while_others_upload(
    stack: Stack, gateway: str, tmp_path: Path
) -> None:
    gateway_log = stack.logs / "gateway-slow-uploads.log"
    offset = gateway_log.stat().st_size
    held = [SlowUpload(gateway, TOKEN, every_s=0.3) for _ in range(PER_TOKEN)]
    try:
        time.sleep(0.5)
        extra = SlowUpload(gateway, TOKEN)
        try:
            status, body = extra.answer()
        finally:
            extra.close()
        assert status == 429
        assert body["error"]["code"] == "too_many_uploads"
        assert body["error"]["message"].startswith(f"this token has {PER_TOKEN} uploads running")
        bag = write_chatter_bag(tmp_path, count=50, name="beside_slow_uploads")
        other = bagmcp("upload", str(bag), "--url", gateway, "--token", OTHER_TOKEN, "--json")
        assert other.returncode == 0, other.stderr
    finally:
        for upload in held:
            upload.close()
    closed = f"went away during POST {UPLOAD_PATH}"
    wait_until(
        lambda: _log_after(gateway_log, offset).count(closed) == PER_TOKEN, timeout_s=10, what="a line per upload"
    )


def test_a_client_that_goes_away_mid_upload_costs_one_log_line(stack: Stack, gateway: str) -> None:
    gateway_log, store_log = stack.logs / "gateway-slow-uploads.log", stack.logs / "bag-store.log"
    offsets = gateway_log.stat().st_size, store_log.stat().st_size
    upload = SlowUpload(gateway, TOKEN)
    upload.sock.sendall(b"x" * 5000)
    time.sleep(0.3)
    upload.close()
    wait_until(lambda: "went away" in _log_after(gateway_log, offsets[0]), timeout_s=10, what="the gateway's line")
    time.sleep(1)
    said = _log_after(gateway_log, offsets[0])
    assert len([line for line in said.splitlines() if "went away" in line]) == 1
    assert "Traceback" not in said
    assert "Traceback" not in _log_after(store_log, offsets[1])


def test_bagmcp_serve_answers_slow_uploads_at_once_and_holds_no_connection(served: str) -> None:
    """More stalled uploads of one token than the limit, and a trickling one: each is answered 405 read_only
    at once (long before the idle time; none 429) and its connection closed, though the client would go on.
    Before, the trickling one's connection stayed open as long as it sent (over 20 s at a byte per 0.5 s)."""
    began = time.monotonic()
    uploads = [SlowUpload(served, TOKEN) for _ in range(PER_TOKEN + 1)] + [SlowUpload(served, TOKEN, every_s=0.2)]
    try:
        for upload in uploads:
            status, body = upload.answer()
            assert status == 405, body
            assert body["error"]["code"] == "read_only"
            assert "uploads are disabled" in body["error"]["message"]
            upload.sock.settimeout(IDLE_S)
            assert upload.sock.recv(100) == b""  # closed by the server, not held for the rest of the body
        assert time.monotonic() - began < IDLE_S
    finally:
        for upload in uploads:
            upload.close()
    assert httpx.get(f"{served}/healthz", timeout=10).status_code == 200
