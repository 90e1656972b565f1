"""The Celery worker entry point: ``celery -A bagmcp_bag_store.worker:app worker`` (takes only the
bag_store queue: ingest and the bag-store's jobs). Settings come from BAGMCP_*; resources are built on
the first task."""

from __future__ import annotations

import functools

from bagmcp_bag_store.settings import QueryLimits
from bagmcp_bag_store.task_refs import RUN_JOB
from bagmcp_bag_store.tasks import register_ingest_task
from bagmcp_bag_store.wiring import BagStoreWork, build_work
from bagmcp_kit.runtime.resources import Resources
from bagmcp_kit.runtime.worker import job_worker
from bagmcp_shared.settings import Env


@functools.cache
def _work(resources: Resources) -> BagStoreWork:
    return build_work(resources, queries=QueryLimits.from_env(Env()))


app, resources = job_worker(RUN_JOB, lambda res: _work(res).registry)
register_ingest_task(app, lambda: _work(resources()).store.ingestor)
