"""A service's Celery worker for its jobs: the task that runs them, bound lazily in the worker process."""

from __future__ import annotations

import functools
import warnings
from collections.abc import Callable

from celery import Celery

from bagmcp_kit.runtime.celery_app import create_celery
from bagmcp_kit.runtime.resources import Resources, team_resources
from bagmcp_shared.jobs import JobRegistry, JobStore, run_job
from bagmcp_shared.settings import Env, TeamSettings
from bagmcp_shared.tasks import TaskRef


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
    return app, resources
