"""A job: long work that tools start, workers run and ``get_job`` follows."""

from __future__ import annotations

import time
import uuid
from typing import Literal

from pydantic import BaseModel, JsonValue

JobState = Literal["queued", "running", "succeeded", "failed", "cancelled"]
TERMINAL: frozenset[str] = frozenset({"succeeded", "failed", "cancelled"})


class Job(BaseModel):
    """The stored record. ``params`` and ``result`` are the JSON of the kind's typed models; ``fetched_bytes``
    what the job fetched from the object store, set when it ended (the call's answer names it)."""

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
    fetched_bytes: int = 0
    created_at: float
    updated_at: float

    @classmethod
    def new(cls, kind: str, owner: str, params: dict[str, JsonValue]) -> Job:
        now = time.time()
        return cls(id=uuid.uuid4().hex[:20], kind=kind, owner=owner, params=params, created_at=now, updated_at=now)

    @property
    def ended(self) -> bool:
        return self.state in TERMINAL
