"""The counters of a service's workers, summed in Redis, so the service's /metrics can show them.

Workers are Celery processes with no HTTP port; what their block caches fetch from S3 would otherwise be on
no /metrics. Each worker process adds what it counted since its last flush into one Redis hash per service
(``bagmcp:worker-counters:<queue>``), field by field with HINCRBY in one MULTI/EXEC, so a reader never sees
half a flush and two processes never lose each other's counts. A flush happens when a task ends (one
round trip per task, none when nothing was counted), never per block. The sums keep growing across worker
restarts, as a Prometheus counter may. Redis being unreachable never fails a task or /metrics: the flush
keeps its counts for the next one, the reader answers None."""

from __future__ import annotations

import logging
import threading
from collections.abc import Callable, Mapping

import redis

log = logging.getLogger(__name__)

_KEY = "bagmcp:worker-counters:"


class WorkerSums:
    """The summed counters of the workers of the service whose queue is ``queue``."""

    def __init__(self, client: redis.Redis, queue: str) -> None:
        self._redis = client
        self._key = _KEY + queue

    def add(self, counts: Mapping[str, int]) -> None:
        """Add ``counts`` to the sums, all or none (raises redis.RedisError when Redis is unreachable)."""
        with self._redis.pipeline(transaction=True) as pipe:
            for name, value in counts.items():
                pipe.hincrby(self._key, name, value)
            pipe.execute()

    def read(self) -> dict[str, int] | None:
        """The sums now (a field no worker has counted yet is absent), or None when Redis is unreachable."""
        try:
            raw = self._redis.hgetall(self._key)
        except redis.RedisError as err:
            log.warning("the workers' counters are unavailable: Redis is unreachable (%s)", err)
            return None
        return {_text(name): int(value) for name, value in raw.items()}


class CounterFlush:
    """What one process counted (``current``: counters since its start) and has not added to ``sums`` yet.
    Flushes are one at a time (a worker pool of threads ends tasks at once; two would add one delta twice)."""

    def __init__(self, sums: WorkerSums, current: Callable[[], dict[str, int]]) -> None:
        self._sums = sums
        self._current = current
        self._flushed: dict[str, int] = {}
        self._lock = threading.Lock()

    def flush(self) -> None:
        """Add the counts since the last flush that reached Redis; nothing when none changed. A failed flush is
        logged and its counts stay for the next one."""
        with self._lock:
            self._flush()

    def _flush(self) -> None:
        now = self._current()
        delta = {name: value - self._flushed.get(name, 0) for name, value in now.items()}
        delta = {name: value for name, value in delta.items() if value}
        if not delta:
            return
        try:
            self._sums.add(delta)
        except redis.RedisError as err:
            log.warning("the worker's counters were not added to Redis; they will be with the next task (%s)", err)
            return
        self._flushed = now


def _text(name: bytes | str) -> str:
    return name.decode() if isinstance(name, bytes) else name
