"""A Celery worker's heartbeat for the tasks it holds: a long task stays with the worker that runs it,
and a dead worker's tasks go to another (see ``create_celery``)."""

from __future__ import annotations

import logging
import threading
import time
from typing import Any, ClassVar

import redis
from celery import bootsteps

log = logging.getLogger(__name__)


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
