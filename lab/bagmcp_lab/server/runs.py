"""Benchmark runs started from the page: long work in the server's event loop with progress (runs done of
runs planned, each record as soon as it is judged), owned by the caller's token and bounded per token.

Runs live in this process's memory (the last ``kept_runs``); a restart forgets them, and the page offers each
run's results.json for download. With several Lab replicas, route a caller to one replica (sticky)."""

from __future__ import annotations

import asyncio
import time
import uuid
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from typing import Any

from bagmcp_lab.errors import LabError, TooManyRunsError
from bagmcp_lab.results import RunRecord
from bagmcp_lab.runner import BenchmarkPlan, run_benchmark
from bagmcp_lab.tasks.suites import Suite


class RunNotFoundError(LabError):
    """No run with this id belongs to the caller."""


@dataclass
class LabRun:
    run_id: str
    owner: str
    plan: BenchmarkPlan
    state: str = "running"  # running, succeeded, failed, cancelled
    planned: int = 0
    records: list[RunRecord] = field(default_factory=list)
    tasks: list[dict[str, str]] = field(default_factory=list)  # id, title, prompt of each task asked
    skipped: dict[str, str] = field(default_factory=dict)
    error: str | None = None
    cancelled: bool = False
    started_s: float = field(default_factory=time.time)
    finished_s: float | None = None

    def status(self) -> dict[str, Any]:
        return {
            "run_id": self.run_id,
            "state": self.state,
            "provider": self.plan.choice.provider,
            "model": self.plan.choice.model,
            "bag": self.plan.bag,
            "suite": self.plan.tasks,
            "repeat": self.plan.repeat,
            "planned": self.planned,
            "done": len(self.records),
            "succeeded": sum(r.success for r in self.records),
            "tasks": self.tasks,
            "skipped": self.skipped,
            "error": self.error,
            "started_s": self.started_s,
            "finished_s": self.finished_s,
            "records": [r.model_dump(mode="json") for r in self.records],
        }


@dataclass
class RunRegistry:
    per_owner: int
    kept: int = 50
    runs: dict[str, LabRun] = field(default_factory=dict)
    _busy: dict[str, int] = field(default_factory=dict)
    _tasks: set[asyncio.Task[None]] = field(default_factory=set)

    def acquire(self, owner: str) -> None:
        """Take one of the owner's places for work going at once (runs and chat turns alike)."""
        if self._busy.get(owner, 0) >= self.per_owner:
            raise TooManyRunsError(
                f"you already have {self.per_owner} Lab runs or chats going; wait for one to finish or cancel it"
            )
        self._busy[owner] = self._busy.get(owner, 0) + 1

    def release(self, owner: str) -> None:
        self._busy[owner] -= 1

    @contextmanager
    def slot(self, owner: str) -> Iterator[None]:
        self.acquire(owner)
        try:
            yield
        finally:
            self.release(owner)

    def start(self, owner: str, plan: BenchmarkPlan) -> LabRun:
        run = LabRun(f"run-{uuid.uuid4().hex[:12]}", owner, plan)
        self.acquire(owner)  # refused here, before anything starts, when the owner has no place left

        async def work() -> None:
            try:
                await self._work(run)
            finally:
                self.release(owner)

        try:
            task = asyncio.get_running_loop().create_task(work(), name=run.run_id)
        except RuntimeError:
            self.release(owner)
            raise
        self._tasks.add(task)
        task.add_done_callback(self._tasks.discard)
        self.runs[run.run_id] = run
        self._forget_old()
        return run

    async def _work(self, run: LabRun) -> None:
        async def on_suite(suite: Suite) -> None:
            run.tasks = [{"id": t.id, "title": t.title, "prompt": t.prompt} for t in suite.tasks]
            run.skipped = dict(suite.skipped)
            run.planned = len(suite.tasks) * run.plan.repeat

        async def on_record(record: RunRecord, _done: int, _planned: int) -> None:
            run.records.append(record)

        try:
            await run_benchmark(run.plan, on_record=on_record, on_suite=on_suite)
            run.state = "succeeded"
        except LabError as err:
            run.state, run.error = "failed", str(err)
        except BaseException as err:  # cancelled (whatever the MCP session made of it), or a bug: never "running"
            run.state, run.error = "failed", f"unexpected {type(err).__name__}; see the server log"
            raise
        finally:
            run.finished_s = time.time()
            if run.cancelled:
                run.state, run.error = "cancelled", None

    def get(self, owner: str, run_id: str) -> LabRun:
        run = self.runs.get(run_id)
        if run is None or run.owner != owner:
            raise RunNotFoundError(f"no Lab run {run_id!r} of yours; list yours at /api/v1/lab/runs")
        return run

    def cancel(self, owner: str, run_id: str) -> LabRun:
        run = self.get(owner, run_id)
        run.cancelled = run.state == "running"
        for task in self._tasks:
            if task.get_name() == run_id:
                task.cancel()
        return run

    def mine(self, owner: str) -> list[LabRun]:
        return [run for run in self.runs.values() if run.owner == owner]

    def _forget_old(self) -> None:
        finished = [r for r in self.runs.values() if r.state != "running"]
        for run in finished[: max(0, len(self.runs) - self.kept)]:
            del self.runs[run.run_id]
