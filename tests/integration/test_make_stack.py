"""`make stack` (deploy/stack/run.sh) as a user runs it: the team stack as local processes on free ports with
its own random secrets, a process that dies restarted, bags kept across restarts (and rebuilt from storage
when Redis lost them), two stacks side by side, and Ctrl-C stopping every process."""

from __future__ import annotations

import os
import re
import shutil
import signal
import socket
import stat
import subprocess
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import anyio
import httpx
import pytest
import redis

from bagmcp_cli.stack.environment import DEFAULT_PORTS, WEED_PORTS, ports_of, read_saved
from tests.fixtures.bagfactory import BagKind, write_chatter_bag
from tests.fixtures.mcp_client import call, http_client
from tests.fixtures.processes import BIN, http_ok, wait_until

RUN = Path(__file__).resolve().parents[2] / "deploy/stack/run.sh"
TOKEN = "stack-test-token"
START_TIMEOUT_S = 120

pytestmark = pytest.mark.integration


def _processes_of(stack_dir: Path) -> list[int]:
    """Live processes started for the stack in ``stack_dir`` (they all have its BAGMCP_STACK_DIR), wherever
    they sit in the process tree (a killed worker's children are re-parented)."""
    marker = f"BAGMCP_STACK_DIR={stack_dir}".encode()
    found = []
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit() and int(entry.name) != os.getpid():
            try:
                state = (entry / "stat").read_text().rsplit(")", 1)[1].split()[0]
                if state != "Z" and marker in (entry / "environ").read_bytes().split(b"\0"):
                    found.append(int(entry.name))
            except OSError:
                continue
    return found


class MakeStack:
    """One stack directory, started and stopped with deploy/stack/run.sh."""

    def __init__(self, directory: Path) -> None:
        self.directory = directory
        self.process: subprocess.Popen[bytes] | None = None
        self.log = directory.parent / f"{directory.name}.log"

    @property
    def settings(self) -> dict[str, str]:
        return read_saved(self.directory / "stack.env")

    @property
    def url(self) -> str:
        return f"http://127.0.0.1:{self.settings['GATEWAY_PORT']}"

    def start(self) -> None:
        env = {**os.environ, "BAGMCP_STACK_DIR": str(self.directory), "BAGMCP_DEV_TOKEN": TOKEN}
        env["PATH"] = f"{BIN}:{env['PATH']}"
        for name in DEFAULT_PORTS:
            env.pop(name, None)
        with self.log.open("ab") as log:
            self.process = subprocess.Popen(
                [RUN], env=env, stdout=log, stderr=subprocess.STDOUT, start_new_session=True
            )
        wait_until(lambda: (self.directory / "stack.env").exists(), timeout_s=30, what="the stack's settings")
        wait_until(http_ok(f"{self.url}/readyz"), timeout_s=START_TIMEOUT_S, what="the stack's gateway")

    def stop(self) -> None:
        """Ctrl-C, as in a terminal: every process of the stack ends."""
        assert self.process is not None
        os.kill(self.process.pid, signal.SIGINT)
        try:
            self.process.wait(timeout=40)
        finally:
            if self.process.poll() is None:
                os.killpg(self.process.pid, signal.SIGKILL)
        wait_until(lambda: not _processes_of(self.directory), timeout_s=30, what="every stack process to stop")
        self.process = None

    def pid_of(self, program: str) -> int:
        started = re.findall(rf"started {re.escape(program)} \(pid (\d+)\)", self.log.read_text())
        return int(started[-1])

    def wait_for_line(self, pattern: str, *, timeout_s: float = 30) -> None:
        wait_until(lambda: re.search(pattern, self.log.read_text()) is not None, timeout_s=timeout_s, what=pattern)

    def bags(self) -> dict[str, tuple[str, str]]:
        """name: (id, status) of every bag, as list_bags answers through the gateway."""

        async def listed() -> dict[str, tuple[str, str]]:
            async with http_client(f"{self.url}/mcp", TOKEN) as client:
                bags = (await call(client, "list_bags", limit=500))["bags"]
            return {b["name"]: (b["id"], b["status"]) for b in bags}

        return anyio.run(listed)

    def wait_ready(self, names: list[str]) -> dict[str, tuple[str, str]]:
        wait_until(lambda: all(self.bags().get(n, ("", ""))[1] == "ready" for n in names), timeout_s=60, what="ingest")
        return self.bags()

    def upload(self, path: Path) -> dict[str, Any]:
        command = [str(BIN / "bagmcp"), "upload", str(path), "--url", self.url, "--token", TOKEN]
        result = subprocess.run(command, capture_output=True, text=True, timeout=120, check=False)
        assert result.returncode == 0, result.stderr
        return {"line": result.stdout}

    def ports(self) -> set[int]:
        return {p for name in DEFAULT_PORTS for p in ports_of(name, int(self.settings[name]))}

    def command(self, *args: str) -> subprocess.CompletedProcess[str]:
        """A command with the stack's settings (deploy/stack/run.sh ARGS)."""
        env = {**os.environ, "BAGMCP_STACK_DIR": str(self.directory), "PATH": f"{BIN}:{os.environ['PATH']}"}
        return subprocess.run([str(RUN), *args], env=env, capture_output=True, text=True, timeout=120, check=False)


@pytest.fixture(scope="module")
def stack_a(tmp_path_factory: pytest.TempPathFactory, scenario_bags: dict[BagKind, Path]) -> Iterator[MakeStack]:
    stack = MakeStack(tmp_path_factory.mktemp("make-stack") / "a")
    stack.start()
    try:
        stack.upload(scenario_bags["ros2-mcap"])
        stack.wait_ready(["scenario_mcap"])
        yield stack
    finally:
        if stack.process is not None:
            stack.stop()


def _mode(path: Path) -> int:
    return stat.S_IMODE(path.stat().st_mode)


def test_the_stack_serves_with_its_own_random_secrets_and_keeps_storage_closed(stack_a: MakeStack) -> None:
    assert len(_processes_of(stack_a.directory)) >= 10  # supervisor, redis, weed, 3 services, 3 workers, gateway
    assert httpx.get(f"{stack_a.url}/api/v1/bags").status_code == 401
    settings = stack_a.settings
    assert len(settings["BAGMCP_SERVICE_TOKEN"]) >= 40
    assert socket.gethostname() not in settings["BAGMCP_SERVICE_TOKEN"]  # not derivable from the machine
    for secret in ("stack.env", "redis/redis.conf", "s3/s3.json", "s3/security.toml"):
        assert _mode(stack_a.directory / secret) == 0o600, secret
    assert _mode(stack_a.directory) == 0o700
    filer_port = int(settings["S3_PORT"]) + WEED_PORTS["WEED_FILER_PORT"]
    filer = httpx.get(f"http://127.0.0.1:{filer_port}/buckets/bagmcp/", timeout=5)
    assert filer.status_code == 404  # the filer answers no HTTP; bags are reached through S3 with its keys
    assert "scenario" not in filer.text
    with pytest.raises(redis.AuthenticationError):
        redis.Redis(port=int(settings["REDIS_PORT"]), socket_timeout=5).ping()


def test_a_process_that_dies_is_restarted_and_the_stack_keeps_answering(stack_a: MakeStack, tmp_path: Path) -> None:
    for program in ("bag-store-worker", "bag-store"):
        os.kill(stack_a.pid_of(program), signal.SIGKILL)
        restarted = rf"{program} was killed by signal 9; restarting it in \d+ s\n[\s\S]*started {program} \(pid"
        stack_a.wait_for_line(restarted)
    wait_until(http_ok(f"{stack_a.url}/readyz"), timeout_s=60, what="the stack to be ready again")
    listing = f"{stack_a.url}/api/v1/bags"  # /readyz says what the gateway's last look saw (every 5 s): ask it
    wait_until(http_ok(listing, headers={"Authorization": f"Bearer {TOKEN}"}), timeout_s=60, what="the bag-store")
    stack_a.upload(write_chatter_bag(tmp_path, count=500, name="after_restart"))
    bags = stack_a.wait_ready(["after_restart"])
    assert {"scenario_mcap", "after_restart"} <= bags.keys()


def test_two_stacks_run_side_by_side_on_different_ports(stack_a: MakeStack, tmp_path: Path) -> None:
    stack_b = MakeStack(tmp_path / "b")
    stack_b.start()
    try:
        assert not stack_a.ports() & stack_b.ports()
        assert stack_b.settings["BAGMCP_SERVICE_TOKEN"] != stack_a.settings["BAGMCP_SERVICE_TOKEN"]
        assert stack_b.bags() == {}
        assert "scenario_mcap" in stack_a.bags()
    finally:
        stack_b.stop()
    assert http_ok(f"{stack_a.url}/readyz")()


def test_a_restart_keeps_every_bag_on_the_same_ports(stack_a: MakeStack) -> None:
    before = stack_a.bags()
    assert "scenario_mcap" in before
    assert all(status == "ready" for _, status in before.values())
    ports = stack_a.ports()
    stack_a.stop()
    assert _left_in_tmp(ports) == []  # weed's gRPC sockets are gone with it
    stack_a.start()
    assert stack_a.ports() == ports  # the saved ports, free again
    assert stack_a.bags() == before


def _left_in_tmp(ports: set[int]) -> list[str]:
    return [str(p) for p in Path("/tmp").glob("seaweedfs-*.sock") if int(p.stem.rsplit("-", 1)[-1]) in ports]


def test_a_start_logs_no_noise(stack_a: MakeStack) -> None:
    """No warning a user cannot act on: Celery's root warning, the gateway's start-up race with its upstreams."""
    log = stack_a.log.read_text()
    assert "superuser privileges" not in log
    assert "unhandled errors in a TaskGroup" not in log


def test_bags_lost_with_redis_are_listed_again_from_storage_when_the_stack_starts(stack_a: MakeStack) -> None:
    before = stack_a.bags()
    stack_a.stop()
    shutil.rmtree(stack_a.directory / "redis")  # Redis starts empty: the bag-store rebuilds the catalog from S3
    stack_a.start()
    assert stack_a.wait_ready(list(before)) == before


def test_catalog_rebuild_with_the_stacks_settings_lists_lost_bags_again(stack_a: MakeStack) -> None:
    before = stack_a.bags()
    settings = stack_a.settings
    client = redis.Redis(port=int(settings["REDIS_PORT"]), password=settings["BAGMCP_REDIS_PASSWORD"])
    lost = list(client.scan_iter("bagmcp:catalog:*"))
    assert lost
    client.delete(*lost)
    assert stack_a.bags() == {}
    rebuilt = stack_a.command("bagmcp", "catalog", "rebuild")
    assert rebuilt.returncode == 0, rebuilt.stderr
    assert f"listed {len(before)} bags again ({len(before)} ready, 0 to ingest), skipped 0" in rebuilt.stdout
    assert "API tokens and jobs lived only in Redis and are not rebuilt" in rebuilt.stdout
    assert stack_a.bags() == before
