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
    """Jobs by id. The cancel request is kept apart from the job record, so a worker's progress
    update can never erase it and a cancel can never overwrite a finished job."""

    def put(self, job: Job) -> None: ...
    def get(self, job_id: str) -> Job | None: ...
    def request_cancel(self, job_id: str) -> None: ...


class MemoryJobStore:
    def __init__(self) -> None:
        self._jobs: dict[str, Job] = {}
        self._cancelled: set[str] = set()
        self._lock = threading.Lock()

    def put(self, job: Job) -> None:
        with self._lock:
            self._jobs[job.id] = job

    def get(self, job_id: str) -> Job | None:
        with self._lock:
            job = self._jobs.get(job_id)
            return job.model_copy(update={"cancel_requested": True}) if job and job_id in self._cancelled else job

    def request_cancel(self, job_id: str) -> None:
        with self._lock:
            self._cancelled.add(job_id)


class RedisJobStore:
    def __init__(self, client: redis.Redis) -> None:
        self._redis = client

    def put(self, job: Job) -> None:
        record = job.model_copy(update={"cancel_requested": False})
        try:
            self._redis.set(_KEY + job.id, record.model_dump_json(), ex=_TTL_S)
        except redis.RedisError as err:
            raise StorageError(f"the job store (Redis) is unreachable: {err}") from err

    def get(self, job_id: str) -> Job | None:
        try:
            raw, cancelled = self._redis.mget([_KEY + job_id, _KEY + job_id + ":cancel"])
        except redis.RedisError as err:
            raise StorageError(f"the job store (Redis) is unreachable: {err}") from err
        if not isinstance(raw, bytes):
            return None
        return Job.model_validate_json(raw).model_copy(update={"cancel_requested": cancelled is not None})

    def request_cancel(self, job_id: str) -> None:
        try:
            self._redis.set(_KEY + job_id + ":cancel", b"1", ex=_TTL_S)
        except redis.RedisError as err:
            raise StorageError(f"the job store (Redis) is unreachable: {err}") from err


def update(store: JobStore, job_id: str, **changes: object) -> Job:
    """Change fields of a job that has not ended; an ended job is returned unchanged."""
    job = store.get(job_id)
    if job is None:
        raise JobNotFoundError(f"job {job_id} no longer exists")
    if job.state in TERMINAL:
        return job
    fresh = job.model_copy(update={**changes, "updated_at": time.time()})
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
