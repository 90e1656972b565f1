"""A long call's work runs in a worker, which fetches its blocks from S3: the bytes reach the answer that hands
the result back (the long call's own when its job ended within the time budget, else get_job's) and so the
gateway's audit line, and the service's /metrics shows its workers' counters. Real weed, Redis, workers."""

from __future__ import annotations

import json
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import anyio
import pytest
import redis
from mcp import Client
from mcp.types import CallToolResult

from bagmcp_shared.jobs.store import RedisJobStore
from tests.fixtures.bagfactory import write_transform_bag
from tests.fixtures.mcp_client import fetched_meta, http_client
from tests.fixtures.processes import BIN, http_ok, service, wait_until
from tests.fixtures.servers import free_ports
from tests.integration.stack import Stack, new_token, run_gateway, service_counters

pytestmark = pytest.mark.anyio

FETCHED = ("bagmcp_s3_fetched_bytes_total", "bagmcp_s3_whole_object_bytes_total")  # blocks, objects fetched whole
QUICK_POSES = 20_000  # over the 5,000 decoded inline: a job, done in well under the patient budget
SLOW_POSES = 100_000  # decoding them outlasts the stack's 1 s budget: the call answers with the job


def fetched_by(url: str, process: str) -> int:
    """Bytes ``process`` ("service" or "workers") of the service at ``url`` fetched from S3, by its /metrics."""
    counters = service_counters(url)[process]
    return sum(counters[name] for name in FETCHED)


def audited(log: Path, token: str, tool: str) -> list[Any]:
    """``fetched_bytes`` of each audit record of ``token``'s calls of ``tool``, in order."""
    lines = log.read_text(errors="replace").splitlines()
    records = [json.loads(row) for row in lines if row.startswith(f'{{"token":"{token}"')]
    return [r.get("fetched_bytes") for r in records if r["tool"] == tool]


@dataclass(frozen=True)
class Patient:
    analysis_url: str
    gateway_url: str


@pytest.fixture(scope="module")
def patient(stack: Stack, tmp_path_factory: pytest.TempPathFactory) -> Iterator[Patient]:
    """A gateway whose analysis service waits up to 120 s for a job (the stack's own waits 1 s), beside the
    stack's; its jobs run on the stack's analysis workers (one queue)."""
    analysis_port, gateway_port = free_ports(2)
    data = tmp_path_factory.mktemp("analysis-patient")
    env = {**stack.worker_env, "BAGMCP_PORT": str(analysis_port), "BAGMCP_DATA_DIR": str(data)}
    env["BAGMCP_JOB_BUDGET_S"] = "120"
    url = f"http://127.0.0.1:{analysis_port}"
    upstreams = {**stack.service_urls, "analysis": url}
    with (
        service(
            "analysis-patient",
            [str(BIN / "python"), "-m", "bagmcp_analysis"],
            log_dir=stack.logs,
            ready=http_ok(f"{url}/healthz"),
            env=env,
        ),
        run_gateway(
            stack,
            "gateway-patient",
            gateway_port,
            {"BAGMCP_UPSTREAMS": ",".join(f"{name}={u}/mcp" for name, u in upstreams.items())},
        ),
    ):
        yield Patient(url, f"http://127.0.0.1:{gateway_port}")


async def test_a_long_call_that_waited_for_its_job_names_the_bytes_the_worker_fetched_on_its_audit_line(
    stack: Stack, patient: Patient, tmp_path: Path
) -> None:
    token = new_token(stack, "patient-fetch")
    name = str(stack.upload_ok(write_transform_bag(tmp_path, count=QUICK_POSES, name="quick_poses"))["name"])
    await stack.wait_ready([name])
    analysis = patient.analysis_url
    service_before, workers_before = fetched_by(analysis, "service"), fetched_by(analysis, "workers")
    async with http_client(f"{patient.gateway_url}/mcp", token) as client:
        first = await client.call_tool("analyze_trajectory", {"bag": name})
        assert isinstance(first.structured_content, dict)
        assert "result" in first.structured_content, first.structured_content  # waited for the job
        again = await client.call_tool("analyze_trajectory", {"bag": name})
    figure = fetched_meta(first)
    assert isinstance(figure, int)
    assert figure > 0
    assert fetched_meta(again) is None  # the worker's block cache and opened bag answer it: nothing fetched
    job_part = figure - (fetched_by(analysis, "service") - service_before)  # what the service fetched itself
    assert job_part > 0  # the worker fetched the poses' pages

    def counted() -> bool:  # the worker adds its counts when its task ends, just after the answer
        return fetched_by(analysis, "workers") - workers_before >= job_part

    wait_until(counted, timeout_s=10, what="the workers' counters to grow by what the job fetched")
    log = stack.logs / "gateway-patient.log"
    wait_until(lambda: len(audited(log, "patient-fetch", "analyze_trajectory")) >= 2, timeout_s=10, what="audit")
    assert audited(log, "patient-fetch", "analyze_trajectory") == [figure, None]


async def test_a_job_followed_with_get_job_names_its_bytes_on_get_jobs_audit_line(stack: Stack, tmp_path: Path) -> None:
    token = new_token(stack, "job-fetch")
    name = str(stack.upload_ok(write_transform_bag(tmp_path, count=SLOW_POSES, name="slow_poses"))["name"])
    await stack.wait_ready([name])
    analysis = stack.service_urls["analysis"]
    workers_before = fetched_by(analysis, "workers")
    async with http_client(f"{stack.url}/mcp", token) as client:
        first_id, first = await _followed(client, name)
        _, again = await _followed(client, name)
    job = RedisJobStore(redis.Redis.from_url(stack.redis_url)).get(first_id)
    assert job is not None
    assert job.fetched_bytes > 0
    assert fetched_meta(first) == job.fetched_bytes
    assert fetched_meta(again) is None  # the worker's block cache and opened bag answer it: nothing fetched

    def counted() -> bool:
        return fetched_by(analysis, "workers") - workers_before >= job.fetched_bytes

    wait_until(counted, timeout_s=10, what="the workers' counters to grow by what the job fetched")
    log = stack.logs / "gateway.log"
    wait_until(lambda: job.fetched_bytes in audited(log, "job-fetch", "get_job"), timeout_s=10, what="audit")
    assert [b for b in audited(log, "job-fetch", "get_job") if b is not None] == [job.fetched_bytes]


async def _followed(client: Client, bag: str) -> tuple[str, CallToolResult]:
    """analyze_trajectory as a job followed with get_job: the job's id and get_job's answer once it ended."""
    started = await client.call_tool("analyze_trajectory", {"bag": bag})
    assert isinstance(started.structured_content, dict)
    assert "job" in started.structured_content, "the job ended within the budget; the test needs a longer one"
    job_id = str(started.structured_content["job"]["job_id"])
    with anyio.fail_after(120):
        while True:
            answer = await client.call_tool("get_job", {"job_id": job_id})
            assert isinstance(answer.structured_content, dict)
            if answer.structured_content["state"] not in ("queued", "running"):
                assert answer.structured_content["state"] == "succeeded", answer.structured_content
                return job_id, answer
            await anyio.sleep(0.2)
