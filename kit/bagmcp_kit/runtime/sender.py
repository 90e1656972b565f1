"""Team mode's runner: a service sends its tasks to its workers' queue through Celery, made on the first task
sent.

A service process only sends tasks (its workers run them), and many never send one: a service answers
stored plots, short reads and catalog calls itself, and a test's stack often queues nothing. Importing Celery
(``celery_app``) and building its app cost each service about 0.045 s of CPU at start (median of 7, time
in the process around the import and ``create_celery``, after the service's own imports), so the runner
imports it when it first sends. Workers import Celery anyway (``worker.py``).
"""

from __future__ import annotations

import threading
from typing import TYPE_CHECKING

from bagmcp_shared.tasks import TaskRef

if TYPE_CHECKING:
    from celery import Celery


class CeleryRunner:
    """Team mode: the task goes to its service's queue, where that service's workers take it."""

    def __init__(self, redis_url: str, *, queue: str, visibility_timeout_s: int) -> None:
        self._redis_url = redis_url
        self._queue = queue
        self._visibility_timeout_s = visibility_timeout_s
        self._app: Celery | None = None
        self._making = threading.Lock()

    def submit(self, task: TaskRef, argument: str) -> None:
        self._celery().send_task(task.name, args=[argument], queue=task.queue)

    def _celery(self) -> Celery:
        """The Celery app, made (and Celery imported) by the first task sent."""
        with self._making:
            if self._app is None:
                from bagmcp_kit.runtime.celery_app import create_celery  # deferred: see the module docstring

                self._app = create_celery(
                    self._redis_url, queue=self._queue, visibility_timeout_s=self._visibility_timeout_s
                )
            return self._app
