"""get_job / cancel_job through an in-memory client over the memory job store: a caller follows and
stops only its own jobs, named by the identity the gateway puts in the request metadata."""

from __future__ import annotations

import pytest
from mcp import Client
from mcp.types import CallToolResult, TextContent

from bagmcp_kit.identity import owner_meta
from bagmcp_kit.job_tools import build_jobs_server
from bagmcp_shared.jobs import MemoryJobStore
from bagmcp_shared.jobs.models import Job

pytestmark = pytest.mark.anyio


def _store_with(job: Job) -> MemoryJobStore:
    store = MemoryJobStore()
    store.put(job)
    return store


def _text(answer: CallToolResult) -> str:
    return " ".join(c.text for c in answer.content if isinstance(c, TextContent))


def _fields(answer: CallToolResult) -> dict[str, object]:
    fields = answer.structured_content
    assert isinstance(fields, dict), _text(answer)
    return fields


def _stored(store: MemoryJobStore, job_id: str) -> Job:
    job = store.get(job_id)
    assert job is not None
    return job


async def test_the_owner_follows_a_job_with_its_state_progress_and_result() -> None:
    job = Job.new("search", "alice", {"bag": "drive"}).model_copy(
        update={"state": "succeeded", "progress": 1.0, "message": "done", "result": {"total": 3}}
    )
    async with Client(build_jobs_server(_store_with(job))) as client:
        answer = await client.call_tool("get_job", {"job_id": job.id}, meta=owner_meta("alice"))
    assert not answer.is_error
    fields = _fields(answer)
    assert (fields["state"], fields["progress"], fields["result"]) == ("succeeded", 1.0, {"total": 3})
    assert f"job {job.id}: succeeded (100%) done" in _text(answer)


async def test_another_caller_is_told_the_job_does_not_exist_and_cannot_cancel_it() -> None:
    job = Job.new("filter", "alice", {}).model_copy(update={"state": "running"})
    store = _store_with(job)
    async with Client(build_jobs_server(store)) as client:
        seen = await client.call_tool("get_job", {"job_id": job.id}, meta=owner_meta("bob"))
        stopped = await client.call_tool("cancel_job", {"job_id": job.id}, meta=owner_meta("bob"))
    assert seen.is_error
    assert stopped.is_error
    assert f"no job {job.id!r} of yours exists" in _text(seen)
    assert not _stored(store, job.id).cancel_requested


async def test_cancel_asks_a_running_job_to_stop_and_leaves_an_ended_one_as_it_is() -> None:
    running = Job.new("filter", "alice", {}).model_copy(update={"state": "running"})
    ended = Job.new("search", "alice", {}).model_copy(update={"state": "succeeded", "progress": 1.0})
    store = _store_with(running)
    store.put(ended)
    async with Client(build_jobs_server(store)) as client:
        asked = await client.call_tool("cancel_job", {"job_id": running.id}, meta=owner_meta("alice"))
        late = await client.call_tool("cancel_job", {"job_id": ended.id}, meta=owner_meta("alice"))
    assert _fields(asked)["message"] == "cancellation requested"
    assert _stored(store, running.id).cancel_requested
    assert _fields(late)["state"] == "succeeded"
    assert not _stored(store, ended.id).cancel_requested


async def test_a_call_without_a_gateway_identity_belongs_to_the_local_caller() -> None:
    job = Job.new("search", "local", {})
    async with Client(build_jobs_server(_store_with(job))) as client:
        answer = await client.call_tool("get_job", {"job_id": job.id})
    assert not answer.is_error
    assert _fields(answer)["state"] == "queued"
