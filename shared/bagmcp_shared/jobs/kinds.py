"""Job kinds: a typed entry per kind of long work (parameters, result, the task that runs it),
and the registry a service fills with the functions that do the work."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Generic, TypeVar

from pydantic import BaseModel, JsonValue, ValidationError

from bagmcp_shared.errors import ArgumentError, BagmcpError
from bagmcp_shared.jobs.progress import Progress
from bagmcp_shared.tasks import TaskRef

P = TypeVar("P", bound=BaseModel)
R = TypeVar("R", bound=BaseModel)


@dataclass(frozen=True)
class JobKind(Generic[P, R]):
    """One kind of job. ``name`` is stored with each job (``<service>.<what>``); ``task`` is the
    background task of the service whose workers run it."""

    name: str
    params: type[P]
    result: type[R]
    task: TaskRef

    def dump(self, params: P) -> dict[str, JsonValue]:
        return params.model_dump(mode="json")

    def load(self, raw: dict[str, JsonValue]) -> P:
        try:
            return self.params.model_validate(raw)
        except ValidationError as err:
            raise ArgumentError(f"the job's parameters are not valid for {self.name}: {err}") from err


Work = Callable[[P, Progress], R]


@dataclass(frozen=True)
class _Entry(Generic[P, R]):
    kind: JobKind[P, R]
    work: Work[P, R]

    def run(self, raw: dict[str, JsonValue], progress: Progress) -> dict[str, JsonValue]:
        return self.work(self.kind.load(raw), progress).model_dump(mode="json")


class JobRegistry:
    """The job kinds one process can run, each bound to the function doing the work."""

    def __init__(self) -> None:
        self._entries: dict[str, _Entry[BaseModel, BaseModel]] = {}

    def add(self, kind: JobKind[P, R], work: Work[P, R]) -> None:
        if kind.name in self._entries:
            raise BagmcpError(f"job kind {kind.name} is registered twice")
        self._entries[kind.name] = _Entry(kind, work)  # type: ignore[arg-type]

    def run(self, kind: str, raw: dict[str, JsonValue], progress: Progress) -> dict[str, JsonValue]:
        entry = self._entries.get(kind)
        if entry is None:
            raise BagmcpError(f"this worker cannot run jobs of kind {kind!r}")
        return entry.run(raw, progress)
