"""`make stack` (deploy/stack/run.sh) as a user runs it: the team stack as local processes on free ports with
its own random secrets, a process that dies restarted, bags kept across restarts (and rebuilt from storage
when Redis lost them), two stacks side by side, and Ctrl-C stopping every process."""

from __future__ import annotations

import os
import shutil
import signal
import socket
import stat
from collections.abc import Iterator
from pathlib import Path

import httpx
import pytest
import redis

from bagmcp_cli.stack.environment import DEFAULT_PORTS, SAVED, WEED_PORTS, ports_free, write_saved
from tests.fixtures.bagfactory import BagKind, write_chatter_bag
from tests.fixtures.make_stack import TOKEN, MakeStack, default_ports_lock, processes_of
from tests.fixtures.processes import http_ok, wait_until
from tests.fixtures.servers import weed_grpc_refuses

pytestmark = pytest.mark.integration


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
    assert len(processes_of(stack_a.directory)) >= 10  # supervisor, redis, weed, 3 services, 3 workers, gateway
    assert httpx.get(f"{stack_a.url}/api/v1/bags").status_code == 401
    settings = stack_a.settings
    assert len(settings["BAGMCP_SERVICE_TOKEN"]) >= 40
    # Not derivable from the machine. A host name of 6 or more characters does not turn up in 43 random URL-safe
    # characters by chance (38 in 64**6); a short one does: a machine named "vm" found its name in a token on
    # 2026-11-28 (about 1 in 100 tokens). Two stacks' tokens differ (test_two_stacks_run_side_by_side...).
    host = socket.gethostname()
    assert len(host) < 6 or host not in settings["BAGMCP_SERVICE_TOKEN"]
    for secret in ("stack.env", "redis/redis.conf", "s3/s3.json", "s3/security.toml", "s3/tls/node.key"):
        assert _mode(stack_a.directory / secret) == 0o600, secret
    assert _mode(stack_a.directory) == 0o700
    filer_port = int(settings["S3_PORT"]) + WEED_PORTS["WEED_FILER_PORT"]
    filer = httpx.get(f"http://127.0.0.1:{filer_port}/buckets/bagmcp/", timeout=5)
    assert filer.status_code == 404  # the filer answers no HTTP; bags are reached through S3 with its keys
    assert "scenario" not in filer.text
    master = f"http://127.0.0.1:{int(settings['S3_PORT']) + WEED_PORTS['WEED_MASTER_PORT']}"
    assert httpx.get(f"{master}/col/delete", params={"collection": "bagmcp"}, timeout=5).status_code == 404
    volume = f"http://127.0.0.1:{int(settings['S3_PORT']) + WEED_PORTS['WEED_VOLUME_PORT']}"
    refused = httpx.get(f"{volume}/admin/delete_collection", params={"collection": "bagmcp"}, timeout=5)
    assert refused.status_code == 401
    grpc_ports = [int(settings["S3_PORT"]) + WEED_PORTS[name] for name in WEED_PORTS if name.endswith("GRPC_PORT")]
    assert [weed_grpc_refuses(port) for port in grpc_ports] == ["TLSV13_ALERT_CERTIFICATE_REQUIRED"] * 4
    assert "scenario_mcap" in stack_a.bags()  # still there, still readable through S3
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
    """The second directory was copied from the first (its saved ports are the first's, taken): the second stack
    starts on the default ports where they are free, else on free ones, with its own secrets and bags."""
    stack_b = MakeStack(tmp_path / "b", default_ports=True)
    stack_b.directory.mkdir(mode=0o700)
    write_saved(stack_b.directory / SAVED, {name: stack_a.settings[name] for name in DEFAULT_PORTS})
    with default_ports_lock():
        free = {name: port for name, port in DEFAULT_PORTS.items() if ports_free(name, port, set())}
        stack_b.start()
        try:
            assert not stack_a.ports() & stack_b.ports()
            assert {name: int(stack_b.settings[name]) for name in free} == free
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
