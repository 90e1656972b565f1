"""How jobs look to callers: ``JobInfo`` (what get_job shows) and the answer of a tool whose work
may outlast its time budget: either the result, or the job to follow, never both."""

from __future__ import annotations

from typing import Generic, TypeVar

from pydantic import BaseModel, Field, JsonValue

from bagmcp_shared.jobs import Job, JobState

R = TypeVar("R", bound=BaseModel)


class JobInfo(BaseModel):
    """A job as get_job reports it; ``result`` is set once it succeeded."""

    job_id: str
    kind: str
    state: JobState
    progress: float = Field(description="0..1")
    message: str
    error: str | None = None
    result: JsonValue = None
    created_at: float = Field(description="epoch s")
    updated_at: float = Field(description="epoch s")

    @classmethod
    def of(cls, job: Job, *, with_result: bool = True) -> JobInfo:
        return cls(
            job_id=job.id,
            kind=job.kind,
            state=job.state,
            progress=round(job.progress, 4),
            message=job.message,
            error=job.error,
            result=job.result if with_result else None,
            created_at=job.created_at,
            updated_at=job.updated_at,
        )


class LongAnswer(BaseModel, Generic[R]):
    """``result`` when the work finished within the time budget; otherwise ``job`` (follow it with get_job)."""

    result: R | None = None
    job: JobInfo | None = None
