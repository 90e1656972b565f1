"""The bytes a job fetched reach the answer that hands its result back: the long call's own when the job ended
within the time budget, else get_job's. Served in process behind the gateway with the embedded job store and
thread runner; the job's work counts its reads as a bag reader does (``count_fetched``, what the block cache
calls per fetched block) once the test lets it go."""

from __future__ import annotations

import threading
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Annotated

import anyio
import pytest
from mcp import Client
from pydantic import BaseModel, Field

from bagmcp_gateway.mcp_front.aggregator import build_gateway_server
from bagmcp_gateway.upstreams.upstream import Upstream
from bagmcp_kit.declared import Declared, ServiceTools
from bagmcp_kit.job_tools import build_jobs_server
from bagmcp_kit.longwork import LongWork
from bagmcp_kit.runtime.resources import embedded_resources
from bagmcp_kit.server import new_server
from bagmcp_shared.fetch_tally import count_fetched
from bagmcp_shared.jobs import Progress, run_job
from bagmcp_shared.tasks import TaskRef
from tests.fixtures.mcp_client import fetched_meta

pytestmark = pytest.mark.anyio
RUN_JOB = TaskRef("bagmcp.reads.run_job", "reads")
BLOCK = 1_048_576


class ReadParams(BaseModel):
    blocks: Annotated[int, Field(ge=0, description="how many blocks to read")]


class Read(BaseModel):
    blocks: int


def read(go: threading.Event, params: ReadParams, progress: Progress) -> Read:
    go.wait(10)
    for _block in range(params.blocks):
        count_fetched(BLOCK)
    return Read(blocks=params.blocks)


READS = ServiceTools[threading.Event](
    "reads",
    RUN_JOB,
    (Declared("read_blocks", "Reads blocks, always as a job.", ReadParams, Read, read, str, small=lambda _, p: False),),
)


@dataclass(frozen=True)
class Served:
    upstreams: list[Upstream]
    go: threading.Event


def served(tmp_path: Path, budget_s: float) -> Iterator[Served]:
    (tmp_path / "bags").mkdir()
    embedded = embedded_resources(tmp_path / "bags", tmp_path / "data", job_budget_s=budget_s)
    res = embedded.resources
    go = threading.Event()
    registry = READS.registry(go)
    embedded.runner.bind(RUN_JOB, lambda job_id: run_job(registry, res.job_store, job_id))
    work = LongWork(res.job_store, res.runner, registry, budget_s=res.job_budget_s)
    server = new_server("bagmcp-reads", purpose="Reading.", tools=READS.specs(go, work))
    try:
        jobs = build_jobs_server(res.job_store)
        yield Served([Upstream(name="reads", server=server), Upstream(name="jobs", server=jobs)], go)
    finally:
        embedded.runner.shutdown()


@pytest.fixture
def patient(tmp_path: Path) -> Iterator[Served]:
    """Calls wait up to 30 s for their job, which goes at once."""
    for service in served(tmp_path, 30.0):
        service.go.set()
        yield service


@pytest.fixture
def hasty(tmp_path: Path) -> Iterator[Served]:
    """Calls answer with the job at once; the job goes when the test says."""
    yield from served(tmp_path, 0.0)


async def test_a_call_that_waited_for_its_job_names_the_bytes_the_job_fetched(patient: Served) -> None:
    async with Client(build_gateway_server(patient.upstreams), cache=None) as client:
        done = await client.call_tool("read_blocks", {"blocks": 3})
        none = await client.call_tool("read_blocks", {"blocks": 0})
    assert done.structured_content == {"result": {"blocks": 3}}
    assert fetched_meta(done) == 3 * BLOCK
    assert fetched_meta(none) is None  # nothing fetched: no figure, as for a short call


async def test_a_job_followed_with_get_job_names_its_bytes_on_get_jobs_answer_once_it_ended(
    hasty: Served,
) -> None:
    async with Client(build_gateway_server(hasty.upstreams), cache=None) as client:
        started = await client.call_tool("read_blocks", {"blocks": 2})
        assert isinstance(started.structured_content, dict)
        assert "job" in started.structured_content
        assert fetched_meta(started) is None  # not ended yet: nothing known
        job_id = started.structured_content["job"]["job_id"]
        assert fetched_meta(await client.call_tool("get_job", {"job_id": job_id})) is None
        hasty.go.set()
        with anyio.fail_after(10):
            while (answer := await client.call_tool("get_job", {"job_id": job_id})).structured_content[
                "state"
            ] != "succeeded":
                await anyio.sleep(0.02)
    assert answer.structured_content["result"] == {"blocks": 2}
    assert fetched_meta(answer) == 2 * BLOCK
