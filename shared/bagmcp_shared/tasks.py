"""Background work behind one seam: a thread pool in process (embedded) or Celery (team).

A task is named once (``TaskRef``: name and the queue of the service that runs it); the function
behind it is bound where the process is wired. Tasks take one string (a bag id or a job id).
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from typing import Protocol

from celery import Celery

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


class CeleryRunner:
    """Team mode: the task goes to its service's queue, where that service's workers take it."""

    def __init__(self, app: Celery) -> None:
        self._app = app

    def submit(self, task: TaskRef, argument: str) -> None:
        self._app.send_task(task.name, args=[argument], queue=task.queue)


def create_celery(redis_url: str, *, queue: str, visibility_timeout_s: int = 3600) -> Celery:
    """A Celery app on Redis (broker and results) whose workers take only ``queue``.

    Tasks are acknowledged after they finish; a task whose worker vanished is handed to another
    worker once ``visibility_timeout_s`` has passed (every task here is safe to run twice).
    """
    app = Celery(f"bagmcp-{queue}", broker=redis_url, backend=redis_url)
    app.conf.update(
        task_default_queue=queue,
        task_queues=None,
        task_create_missing_queues=True,
        task_acks_late=True,
        task_reject_on_worker_lost=True,
        worker_prefetch_multiplier=1,
        task_serializer="json",
        result_serializer="json",
        accept_content=["json"],
        task_ignore_result=True,
        broker_connection_retry_on_startup=True,
        broker_transport_options={
            "visibility_timeout": visibility_timeout_s,
            # look for abandoned tasks every few seconds (kombu's default is about 100 s)
            "unacked_restore_interval": min(10, max(1, visibility_timeout_s // 5)),
            "unacked_restore_throttle": 1,
        },
    )
    return app
