"""A call about a bag still being ingested waits for it within the budget, with progress, then answers; past
the budget it says how far the ingest is and when to ask again."""

from __future__ import annotations

import threading
import time

import pytest
from mcp import Client
from mcp.server.mcpserver import MCPServer
from mcp.types import CallToolResult
from pydantic import BaseModel

from bagmcp_kit.declared import Declared, short_specs
from bagmcp_kit.ingest_wait import IngestWait, bag_refs
from bagmcp_kit.server import new_server
from bagmcp_shared.catalog import BagRecord, MemoryCatalog, resolve_bag
from bagmcp_shared.errors import BagmcpError
from bagmcp_shared.jobs import Progress
from tests.fixtures.mcp_client import text_of

pytestmark = pytest.mark.anyio


def _catalog() -> MemoryCatalog:
    catalog = MemoryCatalog()
    record = BagRecord(
        id="b1", name="run1", layout="file", files=["run1.bag"], source="", in_store=False, sha256="", size_bytes=1,
        created_at=time.time(), progress=0.1,
    )  # fmt: skip
    catalog.add(record)
    return catalog


class BagParams(BaseModel):
    bag: str


class Status(BaseModel):
    status: str


def status_of(catalog: MemoryCatalog, params: BagParams, progress: Progress) -> Status:
    try:
        return Status(status=resolve_bag(catalog, params.bag).status)
    except BagmcpError:
        return Status(status="unknown")


STATUS_OF = Declared[MemoryCatalog, BagParams, Status](
    "status_of", "The bag's status as the tool finds it.", BagParams, Status, status_of, lambda r: r.status, long=False
)


def _server(catalog: MemoryCatalog, budget_s: float) -> MCPServer:
    """A service as the kit builds it, waiting for ingest as every service does."""
    tools = short_specs(catalog, [STATUS_OF])
    return new_server("s", purpose="Test.", tools=tools, ingest=IngestWait(catalog, budget_s))


def _status(answer: CallToolResult) -> str:
    assert isinstance(answer.structured_content, dict)
    return str(answer.structured_content["status"])


def _ingest_later(catalog: MemoryCatalog, *, steps: int, step_s: float) -> threading.Thread:
    def run() -> None:
        for step in range(1, steps + 1):
            time.sleep(step_s)
            record = catalog.get("b1")
            assert record is not None
            done = step == steps
            catalog.replace(
                record.model_copy(update={"progress": step / steps, "status": "ready" if done else "ingesting"})
            )

    thread = threading.Thread(target=run, daemon=True)
    thread.start()
    return thread


async def test_a_call_waits_for_the_ingest_and_reports_its_progress() -> None:
    catalog = _catalog()
    seen: list[float] = []

    async def on_progress(progress: float, total: float | None, message: str | None) -> None:
        seen.append(progress)
        assert message == "waiting for run1 to be ingested"

    _ingest_later(catalog, steps=4, step_s=0.25)
    async with Client(_server(catalog, budget_s=10), cache=None) as client:
        answer = await client.call_tool("status_of", {"bag": "run1"}, progress_callback=on_progress)
    assert not answer.is_error
    assert _status(answer) == "ready"
    assert seen[0] == pytest.approx(0.1)
    assert len(set(seen)) >= 3  # the ingest's own progress, as it went


async def test_past_the_budget_the_answer_says_how_far_and_when_to_ask_again() -> None:
    catalog = _catalog()
    _ingest_later(catalog, steps=20, step_s=0.3)
    async with Client(_server(catalog, budget_s=1.0), cache=None) as client:
        answer = await client.call_tool("status_of", {"bag": "run1"})
    assert answer.is_error
    text = text_of(answer)
    assert text.startswith("bag run1 is still being ingested (")
    assert "% done after waiting 1 s); ask again in about " in text


async def test_unknown_bags_and_calls_without_a_bag_pass_straight_through() -> None:
    async with Client(_server(_catalog(), budget_s=5), cache=None) as client:
        started = time.monotonic()
        assert _status(await client.call_tool("status_of", {"bag": "nope"})) == "unknown"
        assert time.monotonic() - started < 1.0


def test_the_bags_a_call_names_come_from_bag_and_bags() -> None:
    assert bag_refs({"arguments": {"bag": "a", "bags": ["b", 3, " "], "x": "c"}}) == ["a", "b"]
    assert bag_refs({"arguments": None}) == []
