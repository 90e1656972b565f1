"""Tools that may run long: start a job, relay its progress, answer with the result or the job id."""

from __future__ import annotations

import time

import anyio
from mcp.server.mcpserver import Context
from pydantic import JsonValue

from bagmcp_bag_store.deps import BagStoreDeps
from bagmcp_bag_store.jobs import TERMINAL, Job, owned
from bagmcp_bag_store.results import JobInfo

OWNER_META_KEY = "bagmcp/owner"


def owner_of(ctx: Context) -> str:
    """Who called: set by the gateway (which alone holds the service credential); "local" in process."""
    meta = ctx.request_context.meta or {}
    owner = meta.get(OWNER_META_KEY)
    return str(owner) if owner else "local"


def job_info(job: Job) -> JobInfo:
    return JobInfo(
        job_id=job.id,
        kind=job.kind,
        state=job.state,
        progress=round(job.progress, 4),
        message=job.message,
        error=job.error,
        result=job.result,
        created_at=job.created_at,
        updated_at=job.updated_at,
    )


async def start_and_wait(deps: BagStoreDeps, ctx: Context, kind: str, params: dict[str, JsonValue]) -> Job:
    """Queue a job and wait for it up to the time budget, sending progress notifications."""
    job = Job.new(kind, owner_of(ctx), params)
    await anyio.to_thread.run_sync(deps.jobs.put, job)
    await anyio.to_thread.run_sync(deps.submit_job, job.id)
    deadline = time.monotonic() + deps.job_budget_s
    reported = -1.0
    while True:
        current = await anyio.to_thread.run_sync(deps.jobs.get, job.id)
        assert current is not None
        if current.progress != reported:
            reported = current.progress
            await ctx.report_progress(current.progress, 1.0, current.message or current.state)
        if current.state in TERMINAL or time.monotonic() >= deadline:
            return current
        await anyio.sleep(0.1)


def get_job(deps: BagStoreDeps, ctx: Context, job_id: str) -> JobInfo:
    return job_info(owned(deps.jobs, job_id, owner_of(ctx)))


def cancel_job(deps: BagStoreDeps, ctx: Context, job_id: str) -> JobInfo:
    job = owned(deps.jobs, job_id, owner_of(ctx))
    if job.state in TERMINAL:
        return job_info(job)
    deps.jobs.request_cancel(job_id)
    return job_info(owned(deps.jobs, job_id, job.owner).model_copy(update={"message": "cancellation requested"}))
