"""`bagmcp serve` on a port another program holds: one clear line, and no line saying it serves."""

from __future__ import annotations

import socket
import subprocess
from pathlib import Path

from tests.fixtures.processes import BIN


def test_a_busy_port_is_one_clear_line_and_nothing_claims_to_serve(tmp_path: Path) -> None:
    with socket.socket() as holder:
        holder.bind(("127.0.0.1", 0))
        holder.listen()
        port = holder.getsockname()[1]
        done = subprocess.run(
            [str(BIN / "bagmcp"), "serve", "--bags", str(tmp_path), "--port", str(port), "--data", str(tmp_path / "d")],
            capture_output=True,
            text=True,
            timeout=120,
        )
    assert done.returncode == 1
    assert done.stderr.strip().splitlines() == [
        f"bagmcp: error: port {port} on 127.0.0.1 is in use (another bagmcp?); stop that server or pick another port"
    ]
