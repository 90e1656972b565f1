"""The distributed stack as real processes: bag-store, Celery worker(s) and gateway over real
redis-server and weed S3. Used by the session-wide ``stack`` fixture in conftest.py."""

from __future__ import annotations

import json
import os
import signal
import subprocess
from contextlib import ExitStack
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import anyio
from minio import Minio

from tests.fixtures.mcp_client import call, http_client
from tests.fixtures.processes import BIN, http_ok, service
from tests.fixtures.servers import S3Endpoint, free_port

TOKEN = "test-client-token"
OTHER_TOKEN = "test-other-client-token"
SERVICE_TOKEN = "test-service-token"
JOB_BUDGET_S = 1.0
VISIBILITY_TIMEOUT_S = 5
WORKER = [
    "-A",
    "bagmcp_bag_store.worker:app",
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
    workers: list[subprocess.Popen[bytes]] = field(default_factory=list)

    def start_worker(self) -> subprocess.Popen[bytes]:
        name = f"worker-{len(self.workers) + 1}"
        proc = self.exits.enter_context(
            service(name, [str(BIN / "celery"), *WORKER], env=self.worker_env, log_dir=self.logs)
        )
        self.workers.append(proc)
        return proc

    def kill_worker(self, proc: subprocess.Popen[bytes]) -> None:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.wait(timeout=10)

    def upload(self, path: Path) -> subprocess.CompletedProcess[str]:
        command = [str(BIN / "bagmcp"), "upload", str(path), "--url", self.url, "--token", TOKEN, "--json"]
        return subprocess.run(command, capture_output=True, text=True, timeout=300, check=False)

    def upload_ok(self, path: Path) -> dict[str, Any]:
        result = self.upload(path)
        assert result.returncode == 0, result.stderr
        return json.loads(result.stdout)  # type: ignore[no-any-return]

    def objects(self) -> list[str]:
        client = Minio(self.s3.endpoint, access_key=self.s3.access_key, secret_key=self.s3.secret_key, secure=False)
        return sorted(str(o.object_name) for o in client.list_objects(self.bucket, recursive=True))

    async def wait_ready(self, names: list[str], *, timeout_s: float = 120) -> None:
        async with http_client(f"{self.url}/mcp", TOKEN) as client:
            with anyio.fail_after(timeout_s):
                while True:
                    bags = {b["name"]: b["status"] for b in (await call(client, "list_bags", limit=500))["bags"]}
                    if all(bags.get(n) == "ready" for n in names):
                        return
                    await anyio.sleep(0.3)


def start_stack(redis_url: str, s3: S3Endpoint, work: Path, exits: ExitStack) -> Stack:
    logs, store_data, worker_data = (work / n for n in ("logs", "bag-store", "worker"))
    for directory in (logs, store_data, worker_data):
        directory.mkdir(parents=True)
    bucket = f"stack-{free_port()}"
    store_port, gateway_port = free_port(), free_port()
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
    }
    store_url = f"http://127.0.0.1:{store_port}"
    exits.enter_context(
        service(
            "bag-store",
            [str(BIN / "python"), "-m", "bagmcp_bag_store"],
            log_dir=logs,
            ready=http_ok(f"{store_url}/healthz"),
            env={**common, "BAGMCP_PORT": str(store_port), "BAGMCP_DATA_DIR": str(store_data)},
        )
    )
    stack = Stack(
        f"http://127.0.0.1:{gateway_port}",
        store_url,
        s3,
        bucket,
        logs,
        store_data,
        {**common, "BAGMCP_DATA_DIR": str(worker_data)},
        exits,
    )
    stack.start_worker()
    gateway_env = {
        "BAGMCP_SERVICE_TOKEN": SERVICE_TOKEN,
        "BAGMCP_TOKENS": f"{TOKEN},{OTHER_TOKEN}",
        "BAGMCP_PORT": str(gateway_port),
        "BAGMCP_UPSTREAMS": f"bag-store={store_url}/mcp",
        "BAGMCP_BAG_STORE_URL": store_url,
    }
    exits.enter_context(
        service(
            "gateway",
            [str(BIN / "bagmcp"), "gateway"],
            env=gateway_env,
            log_dir=logs,
            ready=http_ok(f"{stack.url}/readyz"),
        )
    )
    return stack
