"""A service's Celery worker for its jobs: the task that runs them, bound lazily in the worker process, and
the flush of the process's counters into the service's sums when a task ends."""

from __future__ import annotations

import functools
import threading
import warnings
from collections.abc import Callable

from celery import Celery
from celery.signals import task_postrun

from bagmcp_kit.runtime.celery_app import create_celery
from bagmcp_kit.runtime.resources import Resources, team_resources
from bagmcp_shared.jobs import JobRegistry, JobStore, run_job
from bagmcp_shared.settings import Env, TeamSettings
from bagmcp_shared.tasks import TaskRef
from bagmcp_shared.worker_counters import CounterFlush


def register_job_task(
    app: Celery, task: TaskRef, registry: Callable[[], JobRegistry], jobs: Callable[[], JobStore]
) -> None:
    """Bind ``task`` to running jobs; ``registry`` and ``jobs`` are called in the worker process."""

    @app.task(name=task.name)  # type: ignore[untyped-decorator]
    def job(job_id: str) -> str:
        return str(run_job(registry(), jobs(), job_id))


def job_worker(task: TaskRef, build: Callable[[Resources], JobRegistry]) -> tuple[Celery, Callable[[], Resources]]:
    """A Celery app that takes only ``task.queue`` and runs its jobs (settings from BAGMCP_*); also returns
    the lazily built resources, for services with more tasks than jobs."""
    # Celery warns "running the worker with superuser privileges" once per worker (three times a `make stack`
    # start) when run as root, as in a dev container; nothing here accepts pickle, which is what it guards.
    warnings.filterwarnings("ignore", message="You're running the worker with superuser privileges")
    settings = TeamSettings.from_env(Env())
    app = create_celery(settings.redis_url, queue=task.queue, visibility_timeout_s=settings.task_visibility_timeout_s)
    resources = functools.cache(lambda: team_resources(settings, queue=task.queue))
    registry = functools.cache(lambda: build(resources()))
    register_job_task(app, task, registry, lambda: resources().job_store)
    flush_counters_after_tasks(app, lambda: resources() if resources.cache_info().currsize else None)
    return app, resources


def flush_counters_after_tasks(app: Celery, built: Callable[[], Resources | None]) -> None:
    """When a task of ``app`` ends, add what this worker process counted since its last flush to the service's
    sums in Redis (its /metrics shows them; worker_counters.py); nothing while ``built`` (the process's resources
    once built) is None. One flush per task end: an HINCRBY per changed counter in one round trip."""
    flushes: list[CounterFlush] = []
    first = threading.Lock()

    def flushed(sender: object = None, **_: object) -> None:
        if getattr(sender, "app", None) is not app or (resources := built()) is None or resources.worker_sums is None:
            return
        with first:  # one flush state per process, also when a pool of threads ends its first tasks at once
            if not flushes:
                flushes.append(CounterFlush(resources.worker_sums, resources.counters))
        flushes[0].flush()

    task_postrun.connect(flushed, weak=False)
