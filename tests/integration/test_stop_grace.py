"""A stopping process (SIGTERM: `docker compose stop`, `make stack`'s supervisor) gives the requests still open
BAGMCP_STOP_GRACE_S to end, then closes them and exits. Before, uvicorn waited for them without limit, and a
service always has some open (the gateway's links, a call waiting for its job), so every stop ended in SIGKILL
after Docker's 10 s. Shown on `bagmcp serve`, which runs the same server start as every service."""

from __future__ import annotations

import signal
import socket
import subprocess
import time
from pathlib import Path

import pytest

from tests.fixtures.processes import BIN, http_ok, service
from tests.fixtures.servers import free_port

pytestmark = pytest.mark.integration

GRACE_S = 1


def _hanging_request(port: int) -> socket.socket:
    """A connection whose POST has sent its headers and a part of the body it announced: a request in progress."""
    conn = socket.create_connection(("127.0.0.1", port), timeout=10)
    head = (
        f"POST /mcp HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nContent-Type: application/json\r\n"
        "Accept: application/json, text/event-stream\r\nContent-Length: 1000\r\n\r\n"
    )
    conn.sendall(head.encode() + b'{"jsonrpc": "2.0", ')
    return conn


def test_a_stop_ends_the_process_within_its_grace_while_a_request_is_still_open(tmp_path: Path) -> None:
    port, bags = free_port(), tmp_path / "bags"
    bags.mkdir()
    command = [str(BIN / "bagmcp"), "serve", "--bags", str(bags), "--port", str(port), "--data", str(tmp_path / "d")]
    env = {"BAGMCP_STOP_GRACE_S": str(GRACE_S)}
    ready = http_ok(f"http://127.0.0.1:{port}/healthz")
    with service("serve-grace", command, env=env, log_dir=tmp_path, ready=ready, stop_timeout_s=1) as proc:
        conn = _hanging_request(port)
        try:
            time.sleep(0.5)  # the server has read the headers and waits for the rest of the body
            began = time.monotonic()
            proc.send_signal(signal.SIGTERM)
            try:
                code = proc.wait(timeout=GRACE_S + 8)
            except subprocess.TimeoutExpired:
                pytest.fail(f"still running {GRACE_S + 8} s after SIGTERM with a request open (grace {GRACE_S} s)")
            took = time.monotonic() - began
        finally:
            conn.close()
    assert code in (0, -signal.SIGTERM), code  # uvicorn ends by raising the signal it caught again
    assert GRACE_S * 0.8 <= took < GRACE_S + 4, took  # it waited for the request, then no longer than the grace
