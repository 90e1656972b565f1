"""What running work reports to: progress (throttled) and the owner's cancel request."""

from __future__ import annotations

import time
from typing import Protocol

from bagmcp_shared.errors import JobCancelledError
from bagmcp_shared.jobs.store import JobStore, update


class Progress(Protocol):
    """Long work calls this with a fraction in 0..1 and a short message; it raises
    JobCancelledError once the owner asked to stop. ``cancelled`` lets work poll without reporting."""

    def __call__(self, fraction: float, message: str) -> None: ...
    def cancelled(self) -> bool: ...


class ProgressReporter:
    """Progress of a stored job."""

    def __init__(self, store: JobStore, job_id: str, *, every_s: float = 0.3) -> None:
        self._store = store
        self._id = job_id
        self._every_s = every_s
        self._last = 0.0

    def __call__(self, fraction: float, message: str) -> None:
        now = time.monotonic()
        if now - self._last < self._every_s and fraction < 1.0:
            return
        self._last = now
        job = update(self._store, self._id, progress=max(0.0, min(1.0, fraction)), message=message)
        if job.cancel_requested:
            raise JobCancelledError(f"job {self._id} was cancelled")

    def cancelled(self) -> bool:
        job = self._store.get(self._id)
        return job is not None and job.cancel_requested


class Unreported:
    """Progress of work run inline (no job): nothing to record, nothing to cancel."""

    def __call__(self, fraction: float, message: str) -> None:
        return None

    def cancelled(self) -> bool:
        return False


class ProgressSpan:
    """One step of longer work: reports its own 0..1 as ``start``..``end`` of the whole, so the whole
    never goes backwards while the steps run one after another."""

    def __init__(self, progress: Progress, start: float, end: float) -> None:
        self._progress = progress
        self._start = start
        self._width = end - start

    def __call__(self, fraction: float, message: str) -> None:
        self._progress(self._start + self._width * max(0.0, min(1.0, fraction)), message)

    def cancelled(self) -> bool:
        return self._progress.cancelled()


def spans(progress: Progress, steps: int) -> list[ProgressSpan]:
    """``steps`` equal spans of the whole, in order."""
    return [ProgressSpan(progress, i / steps, (i + 1) / steps) for i in range(steps)]
