"""The Celery worker entry point: ``celery -A bagmcp_bag_store.worker:app worker``.

Settings come from the environment (BAGMCP_*); dependencies are built on the first task.
"""

from __future__ import annotations

import functools

from bagmcp_bag_store.deps import BagStoreDeps
from bagmcp_bag_store.settings import BagStoreSettings
from bagmcp_bag_store.tasks import create_celery, register_tasks
from bagmcp_bag_store.wiring import team_deps

settings = BagStoreSettings.from_env()
assert settings.redis_url is not None
app = create_celery(settings.redis_url, visibility_timeout_s=settings.task_visibility_timeout_s)


@functools.cache
def _deps() -> BagStoreDeps:
    return team_deps(settings, app)


register_tasks(app, _deps)
