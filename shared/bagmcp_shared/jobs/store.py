"""Job records by id, in memory (embedded) or in Redis (team), with change notifications.

The cancel request is kept apart from the job record, so a worker's progress update can never
erase it and a cancel can never overwrite a finished job. Every write notifies waiters, so a
tool waiting for its job answers the moment it ends instead of at the next poll.
"""

from __future__ import annotations

import threading
import time
from typing import Protocol

import redis

from bagmcp_shared.errors import JobNotFoundError
from bagmcp_shared.jobs.models import Job
from bagmcp_shared.redis_errors import reachable

_KEY = "bagmcp:job:"
_EVENTS = "bagmcp:job-events:"
TTL_S = 7 * 24 * 3600


class JobStore(Protocol):
    def put(self, job: Job) -> None: ...
    def get(self, job_id: str) -> Job | None: ...
    def request_cancel(self, job_id: str) -> None: ...
    def wait(self, job_id: str, *, newer_than: float, timeout_s: float) -> Job | None:
        """The job once its ``updated_at`` passes ``newer_than`` (or it ended), else after ``timeout_s``
        as it is then; blocks without polling."""
        ...


class MemoryJobStore:
    def __init__(self) -> None:
        self._jobs: dict[str, Job] = {}
        self._cancelled: set[str] = set()
        self._changed = threading.Condition()

    def put(self, job: Job) -> None:
        with self._changed:
            self._jobs[job.id] = job
            self._changed.notify_all()

    def get(self, job_id: str) -> Job | None:
        with self._changed:
            job = self._jobs.get(job_id)
            return job.model_copy(update={"cancel_requested": True}) if job and job_id in self._cancelled else job

    def request_cancel(self, job_id: str) -> None:
        with self._changed:
            self._cancelled.add(job_id)
            self._changed.notify_all()

    def cancel_unfinished(self) -> None:
        """Ask every job that has not ended to stop (the process is shutting down)."""
        with self._changed:
            self._cancelled.update(i for i, job in self._jobs.items() if not job.ended)
            self._changed.notify_all()

    def wait(self, job_id: str, *, newer_than: float, timeout_s: float) -> Job | None:
        with self._changed:
            self._changed.wait_for(lambda: _fresh(self.get(job_id), newer_than), timeout=max(timeout_s, 0.0))
            return self.get(job_id)


def _fresh(job: Job | None, newer_than: float) -> bool:
    return job is None or job.updated_at > newer_than or job.ended


class RedisJobStore:
    """Jobs of every service in one Redis: ``get_job`` follows them all."""

    def __init__(self, client: redis.Redis) -> None:
        self._redis = client

    def put(self, job: Job) -> None:
        record = job.model_copy(update={"cancel_requested": False})
        with reachable("the job store"), self._redis.pipeline() as pipe:
            pipe.set(_KEY + job.id, record.model_dump_json(), ex=TTL_S)
            pipe.publish(_EVENTS + job.id, b"1")
            pipe.execute()

    def get(self, job_id: str) -> Job | None:
        with reachable("the job store"):
            raw, cancelled = self._redis.mget([_KEY + job_id, _KEY + job_id + ":cancel"])
        if not isinstance(raw, bytes):
            return None
        return Job.model_validate_json(raw).model_copy(update={"cancel_requested": cancelled is not None})

    def request_cancel(self, job_id: str) -> None:
        with reachable("the job store"), self._redis.pipeline() as pipe:
            pipe.set(_KEY + job_id + ":cancel", b"1", ex=TTL_S)
            pipe.publish(_EVENTS + job_id, b"1")
            pipe.execute()

    def wait(self, job_id: str, *, newer_than: float, timeout_s: float) -> Job | None:
        deadline = time.monotonic() + timeout_s
        with reachable("the job store"), self._redis.pubsub(ignore_subscribe_messages=True) as events:  # type: ignore[no-untyped-call]
            events.subscribe(_EVENTS + job_id)  # subscribe before reading, so no change slips between
            while True:
                job = self.get(job_id)
                remaining = deadline - time.monotonic()
                if _fresh(job, newer_than) or remaining <= 0:
                    return job
                events.get_message(timeout=remaining)


def update(store: JobStore, job_id: str, **changes: object) -> Job:
    """Change fields of a job that has not ended; an ended job is returned unchanged."""
    job = store.get(job_id)
    if job is None:
        raise JobNotFoundError(f"job {job_id} no longer exists")
    if job.ended:
        return job
    fresh = job.model_copy(update={**changes, "updated_at": max(time.time(), job.updated_at + 1e-6)})
    store.put(fresh)
    return fresh


def owned(store: JobStore, job_id: str, owner: str) -> Job:
    """The caller's job; another caller's job is reported as missing, never shown."""
    job = store.get(job_id)
    if job is None or job.owner != owner:
        raise JobNotFoundError(f"no job {job_id!r} of yours exists (jobs are kept for 7 days)")
    return job
