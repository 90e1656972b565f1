"""The distributed stack as real processes: bag-store, Celery worker(s) and gateway over real
redis-server and weed S3. Used by the session-wide ``stack`` fixture in conftest.py."""

from __future__ import annotations

import json
import os
import signal
import subprocess
from contextlib import AbstractContextManager, ExitStack
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import anyio
import httpx
import redis
from minio import Minio

from bagmcp_shared.jobs.store import RedisJobStore
from tests.fixtures.mcp_client import call, http_client
from tests.fixtures.processes import BIN, HTTP, http_ok, scratch_leftovers, service
from tests.fixtures.servers import S3Endpoint, free_port, free_ports

TOKEN = "test-client-token"
OTHER_TOKEN = "test-other-client-token"
SERVICE_TOKEN = "test-service-token"
JOB_BUDGET_S = 1.0
VISIBILITY_TIMEOUT_S = 5
WORKER_FLAGS = [
    "worker",
    "--pool",
    "solo",
    "--concurrency",
    "1",
    "--loglevel",
    "INFO",
    "--without-heartbeat",
    "--without-gossip",
    "--without-mingle",
]
SERVICES = {"bag-store": "bagmcp_bag_store", "analysis": "bagmcp_analysis", "plotting": "bagmcp_plotting"}


@dataclass
class Stack:
    url: str
    bag_store_url: str
    s3: S3Endpoint
    bucket: str
    logs: Path
    bag_store_data: Path
    worker_env: dict[str, str]
    exits: ExitStack
    redis_url: str = ""
    service_urls: dict[str, str] = field(default_factory=dict)
    workers: list[tuple[str, subprocess.Popen[bytes]]] = field(default_factory=list)
    processes: dict[str, subprocess.Popen[bytes]] = field(default_factory=dict)
    data_dirs: dict[str, Path] = field(default_factory=dict)  # each service's and worker's BAGMCP_DATA_DIR

    def start_worker(self, of: str = "bag-store") -> subprocess.Popen[bytes]:
        """A worker of one service (it takes only that service's queue)."""
        name = f"{of}-worker-{len(self.workers) + 1}"
        command = [str(BIN / "celery"), "-A", f"{SERVICES[of]}.worker:app", *WORKER_FLAGS]
        self.data_dirs[name] = self.logs.parent / name
        env = {**self.worker_env, "BAGMCP_DATA_DIR": str(self.data_dirs[name])}
        proc = self.exits.enter_context(service(name, command, env=env, log_dir=self.logs))
        self.workers.append((of, proc))
        return proc

    def latest_worker(self, of: str = "bag-store") -> subprocess.Popen[bytes]:
        return [proc for name, proc in self.workers if name == of][-1]

    def kill_worker(self, proc: subprocess.Popen[bytes]) -> None:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.wait(timeout=10)

    def upload(self, path: Path, *, name: str | None = None) -> subprocess.CompletedProcess[str]:
        command = [str(BIN / "bagmcp"), "upload", str(path), "--url", self.url, "--token", TOKEN, "--json"]
        command += ["--name", name] if name else []
        return subprocess.run(command, capture_output=True, text=True, timeout=300, check=False)

    def upload_ok(self, path: Path, *, name: str | None = None) -> dict[str, Any]:
        result = self.upload(path, name=name)
        assert result.returncode == 0, result.stderr
        return json.loads(result.stdout)  # type: ignore[no-any-return]

    def rest(self, method: str, path: str, **options: Any) -> httpx.Response:
        """A REST call to the gateway with the test token (``path`` under /api/v1)."""
        headers = {"Authorization": f"Bearer {TOKEN}", **options.pop("headers", {})}
        return HTTP.request(method, f"{self.url}/api/v1/{path}", headers=headers, timeout=120, **options)

    def bags(self) -> dict[str, dict[str, Any]]:
        """Every listed bag by name."""
        listing = self.rest("GET", "bags", params={"limit": 500}).json()
        return {b["name"]: b for b in listing["bags"]}

    def upload_leftovers(self) -> list[str]:
        """What the bag-store left in its scratch directory (upload bodies, unpacked archives, temp files)."""
        return scratch_leftovers(self.bag_store_data)

    def objects(self) -> list[str]:
        client = Minio(self.s3.endpoint, access_key=self.s3.access_key, secret_key=self.s3.secret_key, secure=False)
        return sorted(str(o.object_name) for o in client.list_objects(self.bucket, recursive=True))

    async def job_ended(self, job_id: str, *, timeout_s: float = 120) -> None:
        """Wait, reading the job store itself (no MCP call), until a job has ended: an agent that waits
        before its one ``get_job``. The stack's job budget is 1 s so that tests take the job path; on a
        loaded machine a job can still be running when a single ``get_job`` follows at once."""
        store = RedisJobStore(redis.Redis.from_url(self.redis_url))
        with anyio.fail_after(timeout_s):
            while not ((job := store.get(job_id)) is not None and job.ended):
                await anyio.sleep(0.1)

    async def wait_ready(self, names: list[str], *, timeout_s: float = 120) -> None:
        async with http_client(f"{self.url}/mcp", TOKEN) as client:
            with anyio.fail_after(timeout_s):
                while True:
                    bags = {b["name"]: b["status"] for b in (await call(client, "list_bags", limit=500))["bags"]}
                    if all(bags.get(n) == "ready" for n in names):
                        return
                    await anyio.sleep(0.3)


def start_stack(
    redis_url: str, s3: S3Endpoint, work: Path, exits: ExitStack, *, env: dict[str, str] | None = None
) -> Stack:
    """The stack's processes; ``env`` overrides the settings every process gets (the benchmark's job budget)."""
    logs, store_data = work / "logs", work / "bag-store"
    for directory in (logs, store_data):
        directory.mkdir(parents=True)
    bucket = f"stack-{free_port()}"
    ports = dict(zip([*SERVICES, "gateway"], free_ports(len(SERVICES) + 1), strict=True))
    gateway_url = f"http://127.0.0.1:{ports['gateway']}"
    common = {
        "BAGMCP_REDIS_URL": redis_url,
        "BAGMCP_S3_ENDPOINT": s3.endpoint,
        "BAGMCP_S3_ACCESS_KEY": s3.access_key,
        "BAGMCP_S3_SECRET_KEY": s3.secret_key,
        "BAGMCP_S3_BUCKET": bucket,
        "BAGMCP_SERVICE_TOKEN": SERVICE_TOKEN,
        "BAGMCP_JOB_BUDGET_S": str(JOB_BUDGET_S),
        "BAGMCP_S3_READ_TIMEOUT_S": "4",
        "BAGMCP_TASK_VISIBILITY_TIMEOUT_S": str(VISIBILITY_TIMEOUT_S),
        "BAGMCP_ARTIFACT_BASE_URL": gateway_url,
        **(env or {}),
    }
    urls = {name: f"http://127.0.0.1:{ports[name]}" for name in SERVICES}
    processes, data_dirs = {}, {}
    for name, package in SERVICES.items():
        data = data_dirs[name] = store_data if name == "bag-store" else work / name
        processes[name] = exits.enter_context(
            service(
                name,
                [str(BIN / "python"), "-m", package],
                log_dir=logs,
                ready=http_ok(f"{urls[name]}/healthz"),
                env={**common, "BAGMCP_PORT": str(ports[name]), "BAGMCP_DATA_DIR": str(data)},
            )
        )
    stack = Stack(gateway_url, urls["bag-store"], s3, bucket, logs, store_data, dict(common), exits, redis_url, urls)
    stack.processes, stack.data_dirs = processes, data_dirs
    for name in SERVICES:
        stack.start_worker(name)
    stack.processes["gateway"] = exits.enter_context(run_gateway(stack, "gateway", ports["gateway"], {}))
    return stack


def gateway_env(stack: Stack, port: int, extra: dict[str, str]) -> dict[str, str]:
    """The environment of a gateway over the stack's three services (``extra`` overrides it)."""
    urls = stack.service_urls
    return {
        "BAGMCP_SERVICE_TOKEN": SERVICE_TOKEN,
        "BAGMCP_TOKENS": f"{TOKEN},{OTHER_TOKEN}",
        "BAGMCP_PORT": str(port),
        "BAGMCP_UPSTREAMS": ",".join(f"{name}={url}/mcp" for name, url in urls.items()),
        "BAGMCP_REST_ROUTES": f"bags={urls['bag-store']},query={urls['bag-store']},artifacts={urls['plotting']}",
        "BAGMCP_REDIS_URL": stack.redis_url,
        "BAGMCP_RATE_LIMIT_PER_S": "1000",
        "BAGMCP_RATE_BURST": "1000",
        **extra,
    }


def run_gateway(
    stack: Stack, name: str, port: int, extra: dict[str, str]
) -> AbstractContextManager[subprocess.Popen[bytes]]:
    """A gateway process over the stack's services (another replica, or one with other settings)."""
    return service(
        name,
        [str(BIN / "python"), "-m", "bagmcp_gateway"],
        env=gateway_env(stack, port, extra),
        log_dir=stack.logs,
        ready=http_ok(f"http://127.0.0.1:{port}/readyz"),
    )


def bagmcp(*arguments: str) -> subprocess.CompletedProcess[str]:
    """The ``bagmcp`` command of this venv, run to the end."""
    return subprocess.run([str(BIN / "bagmcp"), *arguments], capture_output=True, text=True, timeout=120, check=False)


def new_token(stack: Stack, name: str, *options: str) -> str:
    """A token made through the stack's gateway with `bagmcp token create --url` (``options`` as on the CLI)."""
    made = bagmcp("token", "create", name, *options, "--url", stack.url, "--token", TOKEN, "--json")
    assert made.returncode == 0, made.stderr
    answer: dict[str, Any] = json.loads(made.stdout)
    assert answer["name"] == name
    return str(answer["token"])


def service_counters(url: str) -> dict[str, dict[str, int]]:
    """A service's /metrics (with the service token) as ``{process: {counter: value}}``: ``service`` for its own
    process, ``workers`` for the sums of its workers."""
    answer = httpx.get(f"{url}/metrics", headers={"Authorization": f"Bearer {SERVICE_TOKEN}"}, timeout=10)
    answer.raise_for_status()
    counters: dict[str, dict[str, int]] = {}
    for line in answer.text.splitlines():
        if line.startswith("#"):
            continue
        series, value = line.split(" ")
        name, _, label = series.partition('{process="')
        counters.setdefault(label.removesuffix('"}'), {})[name] = int(value)
    return counters
