"""Background work behind one seam: a thread pool in process (embedded) or Celery (team).

A task is named once (``TaskRef``: name and the queue of the service that runs it); the function
behind it is bound where the process is wired. Tasks take one string (a bag id or a job id).
"""

from __future__ import annotations

import logging
import threading
import time
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from typing import Any, ClassVar, Protocol

import redis
from celery import Celery, bootsteps

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


def create_celery(redis_url: str, *, queue: str, visibility_timeout_s: int = 60) -> Celery:
    """A Celery app on Redis (broker and results) whose workers take only ``queue``.

    Tasks are acknowledged after they finish. A task whose worker vanished (killed outright, its machine
    gone) is handed to another worker once ``visibility_timeout_s`` has passed; a live worker keeps the tasks
    it holds from being handed out again however long they run (``VisibilityHeartbeat``). Every task here is
    safe to run twice.
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
    app.steps["consumer"].add(VisibilityHeartbeat)
    return app


class VisibilityHeartbeat(bootsteps.StartStopStep):  # type: ignore[misc]
    """A worker's heartbeat for the tasks it holds: every quarter of the visibility timeout it marks them as
    just delivered in the broker's index of unacknowledged tasks (the Redis transport hands a task to another
    worker when its mark is older than the visibility timeout). A worker that dies stops marking, so its
    tasks go to another worker within one visibility timeout; one that lives keeps them however long they run.
    """

    requires: ClassVar[tuple[str, ...]] = ("celery.worker.consumer.tasks:Tasks",)

    def __init__(self, parent: Any, **options: Any) -> None:
        super().__init__(parent, **options)
        self._stopped = threading.Event()

    def start(self, consumer: Any) -> None:
        channel = consumer.task_consumer.channel
        timeout_s = float(consumer.app.conf.broker_transport_options["visibility_timeout"])
        client = redis.Redis.from_url(consumer.app.conf.broker_url, socket_timeout=10, socket_connect_timeout=5)
        beat = threading.Thread(
            target=_mark_held, args=(channel, client, timeout_s / 4, self._stopped), name="visibility", daemon=True
        )
        beat.start()

    def stop(self, _consumer: Any) -> None:
        self._stopped.set()


def _held(channel: Any) -> list[str]:
    """Delivery tags this worker holds (read from another thread: retried if it changes meanwhile)."""
    for _ in range(5):
        try:
            qos = channel.qos
            return [t for t in list(qos._delivered) if t not in qos._dirty]
        except RuntimeError:  # changed size during iteration
            continue
    return []


def _mark_held(channel: Any, client: redis.Redis, every_s: float, stopped: threading.Event) -> None:
    while not stopped.wait(every_s):
        tags = _held(channel)
        if not tags:
            continue
        try:  # XX: only tags still unacknowledged (one acknowledged meanwhile is not brought back)
            client.zadd(channel.unacked_index_key, dict.fromkeys(tags, time.time()), xx=True)
        except redis.RedisError as err:
            log.warning("could not renew the visibility of %d held tasks: %s", len(tags), err)
