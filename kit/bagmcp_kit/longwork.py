"""Long work: run it inline when it is small, else start a job and wait for it up to the time budget
(woken by the job store's notifications, relaying progress), then answer with the result or the job. A job
that ended within the budget adds the bytes it fetched (in a worker) to the call's tally, so the answer's
``_meta`` names them as it names what the service fetched itself (fetch_meta.py)."""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import TypeVar

import anyio
from mcp.server.mcpserver import Context
from mcp.server.mcpserver.exceptions import ToolError
from mcp.types import CallToolResult, ContentBlock
from pydantic import BaseModel

from bagmcp_kit.answers import answer, tool_errors
from bagmcp_kit.identity import caller
from bagmcp_kit.job_info import JobInfo, LongAnswer
from bagmcp_shared.fetch_tally import count_fetched
from bagmcp_shared.jobs import Job, JobKind, JobRegistry, JobStore, Unreported
from bagmcp_shared.tasks import Runner

P = TypeVar("P", bound=BaseModel)
R = TypeVar("R", bound=BaseModel)
Attach = Callable[[R], list[ContentBlock]]


class LongWork:
    """Starts and follows the jobs of one service (``registry`` also runs small work inline)."""

    def __init__(self, jobs: JobStore, runner: Runner, registry: JobRegistry, *, budget_s: float) -> None:
        self._jobs = jobs
        self._runner = runner
        self._registry = registry
        self.budget_s = budget_s

    async def run(
        self,
        ctx: Context,
        kind: JobKind[P, R],
        params: P,
        summarize: Callable[[R], str],
        *,
        small: Callable[[P], bool] | None = None,
        inline: Callable[[P], R | None] | None = None,
        attach: Attach[R] | None = None,
    ) -> CallToolResult:
        """The tool's answer: ``{"result": ...}`` when the work is done in time, else ``{"job": ...}``.

        ``small`` (run in a thread) says whether the work is quick enough to do inline, without a job, which
        then runs through the registry; ``inline`` instead does both in one go, answering the result when the
        work is small and None for a job, for work whose estimate and run share what they open;
        ``attach`` adds content for a finished result, such as its image (in the thread that builds the answer)."""
        raw = await self._now(kind, params, small, inline)
        if raw is not None:
            return await self._finished(kind, raw, summarize, attach)
        job = await self.start(ctx, kind, params)
        count_fetched(job.fetched_bytes)  # fetched in a worker for this call (0 until the job ends)
        if job.state == "succeeded" and job.result is not None:
            return await self._finished(kind, job.result, summarize, attach)
        return self._unfinished(job)

    async def _now(
        self,
        kind: JobKind[P, R],
        params: P,
        small: Callable[[P], bool] | None,
        inline: Callable[[P], R | None] | None,
    ) -> object | None:
        """The result of work small enough to do now, in a worker thread; None when it needs a job."""
        with tool_errors():
            if inline is not None:
                return await anyio.to_thread.run_sync(inline, params)
            if small is not None and await anyio.to_thread.run_sync(small, params):
                return await anyio.to_thread.run_sync(self._registry.run, kind.name, kind.dump(params), Unreported())
        return None

    async def start(self, ctx: Context, kind: JobKind[P, R], params: P) -> Job:
        """Queue the job and wait for it up to the budget, sending progress notifications."""
        job = Job.new(kind.name, caller(ctx), kind.dump(params))
        with tool_errors():
            await anyio.to_thread.run_sync(self._jobs.put, job)
            await anyio.to_thread.run_sync(self._runner.submit, kind.task, job.id)
        deadline = time.monotonic() + self.budget_s
        seen, reported = job.updated_at, -1.0
        while True:
            remaining = deadline - time.monotonic()
            with tool_errors():
                current = await anyio.to_thread.run_sync(self._wait, job.id, seen, remaining)
            if current is None:
                raise ToolError(f"job {job.id} vanished from the job store; start the work again")
            seen = current.updated_at
            if current.progress != reported:
                reported = current.progress
                await ctx.report_progress(current.progress, 1.0, current.message or current.state)
            if current.ended or time.monotonic() >= deadline:
                return current

    def _wait(self, job_id: str, seen: float, remaining_s: float) -> Job | None:
        return self._jobs.wait(job_id, newer_than=seen, timeout_s=max(remaining_s, 0.0))

    async def _finished(
        self, kind: JobKind[P, R], raw: object, summarize: Callable[[R], str], attach: Attach[R] | None
    ) -> CallToolResult:
        """The answer of a finished result, built in a worker thread: checking and dumping a large result (200
        matches of whole messages: about 16 ms) would hold up every other call on the event loop."""

        def build() -> CallToolResult:
            result = raw if isinstance(raw, kind.result) else kind.result.model_validate(raw)  # inline: as it is
            with tool_errors():
                extra = attach(result) if attach is not None else []
            return answer(LongAnswer[R](result=result), summarize(result), extra=extra, omit_none=True)

        return await anyio.to_thread.run_sync(build)

    def _unfinished(self, job: Job) -> CallToolResult:
        if job.state == "failed":
            raise ToolError(job.error or "the job failed")
        if job.state == "cancelled":
            raise ToolError(f"job {job.id} was cancelled")
        text = (
            f"still {job.state} after the time budget ({job.progress:.0%}: {job.message}); "
            f"call get_job with job_id {job.id} to follow it, or cancel_job to stop it"
        )
        return answer(LongAnswer[BaseModel](job=JobInfo.of(job, with_result=False)), text, omit_none=True)
