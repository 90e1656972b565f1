"""Long work as jobs: a record per job (state, progress, result) that tools, workers and get_job share."""

from __future__ import annotations

import threading
import time
import uuid
from typing import Literal, Protocol

import redis
from pydantic import BaseModel, JsonValue

from bagmcp_shared.errors import BagmcpError, StorageError

JobState = Literal["queued", "running", "succeeded", "failed", "cancelled"]
TERMINAL: frozenset[str] = frozenset({"succeeded", "failed", "cancelled"})
_KEY = "bagmcp:job:"
_TTL_S = 7 * 24 * 3600


class JobNotFoundError(BagmcpError):
    """No job with this id belongs to the caller."""


class JobCancelledError(BagmcpError):
    """The job's owner cancelled it; the work stops at its next progress report."""


class Job(BaseModel):
    id: str
    kind: str
    owner: str
    state: JobState = "queued"
    progress: float = 0.0
    message: str = ""
    params: dict[str, JsonValue]
    result: dict[str, JsonValue] | None = None
    error: str | None = None
    cancel_requested: bool = False
    created_at: float
    updated_at: float

    @classmethod
    def new(cls, kind: str, owner: str, params: dict[str, JsonValue]) -> Job:
        now = time.time()
        return cls(id=uuid.uuid4().hex[:20], kind=kind, owner=owner, params=params, created_at=now, updated_at=now)


class JobStore(Protocol):
    def put(self, job: Job) -> None: ...
    def get(self, job_id: str) -> Job | None: ...


class MemoryJobStore:
    def __init__(self) -> None:
        self._jobs: dict[str, Job] = {}
        self._lock = threading.Lock()

    def put(self, job: Job) -> None:
        with self._lock:
            self._jobs[job.id] = job

    def get(self, job_id: str) -> Job | None:
        with self._lock:
            return self._jobs.get(job_id)


class RedisJobStore:
    def __init__(self, client: redis.Redis) -> None:
        self._redis = client

    def put(self, job: Job) -> None:
        try:
            self._redis.set(_KEY + job.id, job.model_dump_json(), ex=_TTL_S)
        except redis.RedisError as err:
            raise StorageError(f"the job store (Redis) is unreachable: {err}") from err

    def get(self, job_id: str) -> Job | None:
        try:
            raw = self._redis.get(_KEY + job_id)
        except redis.RedisError as err:
            raise StorageError(f"the job store (Redis) is unreachable: {err}") from err
        return Job.model_validate_json(raw) if isinstance(raw, bytes) else None


def update(store: JobStore, job_id: str, **changes: object) -> Job:
    """Change fields of a stored job (last writer wins; a cancel request is never lost)."""
    job = store.get(job_id)
    if job is None:
        raise JobNotFoundError(f"job {job_id} no longer exists")
    fresh = job.model_copy(update={**changes, "updated_at": time.time()})
    latest = store.get(job_id)
    if latest is not None and latest.cancel_requested:
        fresh = fresh.model_copy(update={"cancel_requested": True})
    store.put(fresh)
    return fresh


def owned(store: JobStore, job_id: str, owner: str) -> Job:
    job = store.get(job_id)
    if job is None or job.owner != owner:
        raise JobNotFoundError(f"no job {job_id!r} of yours exists (jobs are kept for 7 days)")
    return job


class ProgressReporter:
    """What running work calls: records progress (throttled) and raises once cancel is requested."""

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
