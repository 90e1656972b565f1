"""A small service built only from declarations (kit/declared.py), as docs/ADDING_A_SERVICE.md tells: one
short tool and one long-work tool, served in process behind the gateway with the embedded job store and
thread runner, and called through an in-memory MCP client."""

from __future__ import annotations

import threading
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Annotated

import anyio
import pytest
from mcp import Client
from pydantic import BaseModel, ConfigDict, Field

from bagmcp_gateway.mcp_front.aggregator import build_gateway_server
from bagmcp_gateway.upstreams.upstream import Upstream
from bagmcp_kit.arguments import WRITES
from bagmcp_kit.declared import GIVEN, Declared, ServiceTools
from bagmcp_kit.job_tools import build_jobs_server
from bagmcp_kit.longwork import LongWork
from bagmcp_kit.runtime.resources import Embedded, embedded_resources
from bagmcp_kit.server import new_server
from bagmcp_shared.jobs import Progress, run_job
from bagmcp_shared.tasks import TaskRef
from tests.fixtures.mcp_client import JsonObject, call, call_error

pytestmark = pytest.mark.anyio
RUN_JOB = TaskRef("bagmcp.tally.run_job", "tally")


@dataclass(frozen=True)
class Tally:
    """What the tools work on (a real service passes its BagAccess); long counts wait for ``go``, so a test
    sees the job before it ends."""

    unit: str
    go: threading.Event


class ScaleParams(BaseModel):
    value: Annotated[float, Field(description="the number to scale")]
    factor: Annotated[float, Field(gt=0, description="how many times")] = 2.0
    unit: Annotated[str, GIVEN] = "?"  # set by the server, never an argument


class CountParams(BaseModel):
    model_config = ConfigDict(validate_by_name=True, validate_by_alias=True)

    up_to: Annotated[int, Field(ge=1, le=10_000, alias="to", description="the last number")]


class Scaled(BaseModel):
    value: float
    unit: str


class Counted(BaseModel):
    total: int
    unit: str


def scale(tally: Tally, params: ScaleParams, progress: Progress) -> Scaled:
    return Scaled(value=params.value * params.factor, unit=params.unit)


def count(tally: Tally, params: CountParams, progress: Progress) -> Counted:
    if params.up_to > 10:
        tally.go.wait(10)
    total = 0
    for n in range(1, params.up_to + 1):
        total += n
        if n % 1000 == 0:
            progress(n / params.up_to, f"{n} counted")
    return Counted(total=total, unit=tally.unit)


TALLY = ServiceTools[Tally](
    "tally",
    RUN_JOB,
    (
        Declared(
            "scale",
            "A number times a factor.",
            ScaleParams,
            Scaled,
            scale,
            lambda r: f"{r.value}",
            long=False,
            given=lambda ctx, tally: {"unit": tally.unit},
        ),
        Declared(
            "count_up",
            "The sum 1 + 2 + ... + to; up to 10 it is done at once, beyond that as a job.",
            CountParams,
            Counted,
            count,
            lambda r: f"{r.total} {r.unit}",
            annotations=WRITES,
            small=lambda tally, p: p.up_to <= 10,
        ),
    ),
)


@dataclass(frozen=True)
class Served:
    embedded: Embedded
    tally: Tally
    upstreams: list[Upstream]


@pytest.fixture
def served(tmp_path: Path) -> Iterator[Served]:
    """The tally service and the jobs tools behind the gateway; with no time budget a job answers at once."""
    (tmp_path / "bags").mkdir()
    embedded = embedded_resources(tmp_path / "bags", tmp_path / "data", job_budget_s=0.0)
    res = embedded.resources
    tally = Tally("apples", threading.Event())
    registry = TALLY.registry(tally)
    embedded.runner.bind(RUN_JOB, lambda job_id: run_job(registry, res.job_store, job_id))
    work = LongWork(res.job_store, res.runner, registry, budget_s=res.job_budget_s)
    server = new_server("bagmcp-tally", purpose="Counting.", tools=TALLY.specs(tally, work))
    try:
        yield Served(
            embedded,
            tally,
            [Upstream(name="tally", server=server), Upstream(name="jobs", server=build_jobs_server(res.job_store))],
        )
    finally:
        embedded.runner.shutdown()


async def _finished(client: Client, job_id: str) -> JsonObject:
    with anyio.fail_after(10):
        while (job := await call(client, "get_job", job_id=job_id))["state"] not in {"succeeded", "failed"}:
            await anyio.sleep(0.02)
    return job


async def test_the_declared_tools_are_listed_with_the_params_models_schemas(
    served: Served,
) -> None:
    async with Client(build_gateway_server(served.upstreams), cache=None) as client:
        tools = {t.name: t for t in (await client.list_tools()).tools}
    scale_tool, count_tool = tools["scale"], tools["count_up"]
    assert scale_tool.description == "A number times a factor."
    assert scale_tool.input_schema["required"] == ["value"]
    assert set(scale_tool.input_schema["properties"]) == {"value", "factor"}
    assert scale_tool.input_schema["properties"]["factor"]["exclusiveMinimum"] == 0
    assert count_tool.input_schema["required"] == ["to"]
    assert count_tool.input_schema["properties"]["to"]["description"] == "the last number"
    assert count_tool.annotations is not None
    assert count_tool.annotations.read_only_hint is False
    assert scale_tool.output_schema is not None
    assert "value" in scale_tool.output_schema["properties"]
    assert count_tool.output_schema is not None
    assert set(count_tool.output_schema["properties"]) == {"result", "job"}


async def test_a_short_tool_answers_its_result(served: Served) -> None:
    async with Client(build_gateway_server(served.upstreams), cache=None) as client:
        assert await call(client, "scale", value=1.5, factor=4) == {"value": 6.0, "unit": "apples"}
        assert "factor" in await call_error(client, "scale", value=1.5, factor=0)
        assert "unknown argument(s) unit" in await call_error(client, "scale", value=1.5, unit="pears")


async def test_small_long_work_runs_inline_and_large_work_as_a_job_of_the_derived_kind(
    served: Served,
) -> None:
    async with Client(build_gateway_server(served.upstreams), cache=None) as client:
        assert await call(client, "count_up", to=10) == {"result": {"total": 55, "unit": "apples"}}
        started = await call(client, "count_up", to=5000)
        assert started["job"]["kind"] == "tally.count_up"
        assert started["job"]["state"] in {"queued", "running"}
        served.tally.go.set()
        job = await _finished(client, started["job"]["job_id"])
    assert job["state"] == "succeeded"
    assert job["result"] == {"total": 5000 * 5001 // 2, "unit": "apples"}
    stored = served.embedded.resources.job_store.get(started["job"]["job_id"])
    assert stored is not None
    assert stored.params == {"up_to": 5000}


async def test_an_unknown_argument_names_the_valid_ones(served: Served) -> None:
    async with Client(build_gateway_server(served.upstreams), cache=None) as client:
        error = await call_error(client, "count_up", up_to=3)
    assert "unknown argument(s) up_to for count_up; valid arguments: to" in error
