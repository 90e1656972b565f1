"""`make stack` (deploy/stack/run.sh under honcho) brings the team stack up as local processes,
serves a token-protected MCP endpoint, and stops every process on Ctrl-C."""

from __future__ import annotations

import os
import signal
import socket
import subprocess
from pathlib import Path

import anyio
import httpx
import pytest

from tests.fixtures.bagfactory import BagKind
from tests.fixtures.mcp_client import call, http_client
from tests.fixtures.processes import BIN, http_ok, wait_until
from tests.fixtures.servers import free_port, free_ports

ROOT = Path(__file__).resolve().parents[2]
TOKEN = "stack-test-token"

pytestmark = pytest.mark.integration


def _session_members(session: int) -> list[int]:
    """Live processes of a session (honcho and everything it started share the session)."""
    members = []
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                fields = (entry / "stat").read_text().rsplit(")", 1)[1].split()
            except OSError:
                continue
            if int(fields[3]) == session and fields[0] != "Z":
                members.append(int(entry.name))
    return members


def _port_free(port: int) -> bool:
    with socket.socket() as probe:
        try:
            probe.bind(("127.0.0.1", port))
        except OSError:
            return False
    return True


def _s3_base_port(taken: set[int]) -> int:
    """An S3_PORT for deploy/stack/s3.sh, which also uses the next 3 ports and those + 10000."""
    for _ in range(200):
        base = free_port()
        wanted = [base + i for i in range(4)] + [base + 1 + 10000 + i for i in range(4)]
        if base + 3 + 10000 < 65536 and not taken & set(wanted) and all(_port_free(p) for p in wanted):
            return base
    raise RuntimeError("no block of free ports for the stack's S3 server")


def test_make_stack_serves_uploads_and_stops_on_ctrl_c(scenario_bags: dict[BagKind, Path], tmp_path: Path) -> None:
    stack_dir = tmp_path / "stack"
    names = ("GATEWAY_PORT", "BAG_STORE_PORT", "ANALYSIS_PORT", "PLOTTING_PORT", "REDIS_PORT")
    ports = dict(zip(names, free_ports(len(names)), strict=True))
    s3_port = _s3_base_port(set(ports.values()))
    env = {
        **os.environ,
        **{k: str(v) for k, v in ports.items()},
        "S3_PORT": str(s3_port),
        "BAGMCP_STACK_DIR": str(stack_dir),
        "BAGMCP_DEV_TOKEN": TOKEN,
        "PATH": f"{BIN}:{os.environ['PATH']}",
    }
    log = (tmp_path / "stack.log").open("wb")
    proc = subprocess.Popen(
        [str(ROOT / "deploy/stack/run.sh")], env=env, stdout=log, stderr=subprocess.STDOUT, start_new_session=True
    )
    url = f"http://127.0.0.1:{ports['GATEWAY_PORT']}"
    try:
        wait_until(http_ok(f"{url}/readyz"), timeout_s=90, what="the stack's gateway")
        # honcho, redis, weed, three services, three workers, gateway
        assert len(_session_members(proc.pid)) >= 10
        upload = subprocess.run(
            [str(BIN / "bagmcp"), "upload", str(scenario_bags["ros2-mcap"]), "--url", url, "--token", TOKEN],
            capture_output=True,
            text=True,
            timeout=120,
            check=False,
        )
        assert upload.returncode == 0, upload.stderr
        assert httpx.get(f"{url}/api/v1/bags").status_code == 401

        async def listed() -> list[str]:
            async with http_client(f"{url}/mcp", TOKEN) as client:
                with anyio.fail_after(60):
                    while (bags := (await call(client, "list_bags"))["bags"])[0]["status"] != "ready":
                        await anyio.sleep(0.3)
                return [b["name"] for b in bags]

        assert anyio.run(listed) == ["scenario_mcap"]
        assert (stack_dir / "redis").is_dir()
        assert (stack_dir / "s3" / "data").is_dir()
    finally:
        os.killpg(proc.pid, signal.SIGINT)
        try:
            proc.wait(timeout=30)
        finally:
            if proc.poll() is None:
                os.killpg(proc.pid, signal.SIGKILL)
            log.close()
    wait_until(lambda: not _session_members(proc.pid), timeout_s=30, what="every stack process to stop")
