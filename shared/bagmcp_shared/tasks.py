"""Background work behind one seam: a thread pool in process (embedded) here, Celery (team) in the kit's
runtime (``bagmcp_kit.runtime.celery_app``), so the library itself imports no Celery.

A task is named once (``TaskRef``: name and the queue of the service that runs it); the function
behind it is bound where the process is wired. Tasks take one string (a bag id or a job id).
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from typing import Protocol

log = logging.getLogger(__name__)
Handler = Callable[[str], object]


@dataclass(frozen=True)
class TaskRef:
    """``name`` is the Celery task name; ``queue`` the service's own queue (one queue per service)."""

    name: str
    queue: str


class Runner(Protocol):
    def submit(self, task: TaskRef, argument: str) -> None:
        """Hand ``argument`` to ``task``; returns at once (the work runs elsewhere)."""
        ...


class ThreadRunner:
    """Embedded mode: one thread pool per task, so a search never waits behind start-up ingest."""

    def __init__(self) -> None:
        self._pools: dict[TaskRef, ThreadPoolExecutor] = {}
        self._handlers: dict[TaskRef, Handler] = {}
        self._on_shutdown: list[Callable[[], None]] = []

    def bind(self, task: TaskRef, handler: Handler, *, workers: int = 2) -> None:
        self._handlers[task] = handler
        self._pools[task] = ThreadPoolExecutor(max_workers=workers, thread_name_prefix=task.name)

    def on_shutdown(self, callback: Callable[[], None]) -> None:
        self._on_shutdown.append(callback)

    def submit(self, task: TaskRef, argument: str) -> None:
        self._pools[task].submit(_logged, self._handlers[task], task, argument)

    def shutdown(self) -> None:
        """Stop taking work, let running work stop itself, drop what has not started."""
        for callback in self._on_shutdown:
            callback()
        for pool in self._pools.values():
            pool.shutdown(wait=False, cancel_futures=True)


def _logged(handler: Handler, task: TaskRef, argument: str) -> None:
    try:
        handler(argument)
    except Exception:  # a thread has no caller to report to; handlers record failures themselves
        log.exception("%s(%s) failed", task.name, argument)
