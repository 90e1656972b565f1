"""Building the bag-store's dependencies for each way of running it."""

from __future__ import annotations

import logging
import os
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import redis
from celery import Celery

from bagmcp_bag_store.bagfiles import CachedBagFiles, FolderBagFiles
from bagmcp_bag_store.catalog import MemoryCatalog, RedisCatalog
from bagmcp_bag_store.deps import BagStoreDeps
from bagmcp_bag_store.folder import catalog_folder
from bagmcp_bag_store.ingest import ingest_bag
from bagmcp_bag_store.jobrun import run_job
from bagmcp_bag_store.jobs import MemoryJobStore, RedisJobStore
from bagmcp_bag_store.settings import BagStoreSettings
from bagmcp_bag_store.tasks import INGEST_TASK, JOB_TASK, create_celery
from bagmcp_shared.errors import BagmcpError, StorageError
from bagmcp_shared.storage import S3Store

log = logging.getLogger(__name__)


class ThreadRunner:
    """Background work inside this process (embedded mode): ingest and jobs on a small thread pool."""

    def __init__(self, workers: int = 2) -> None:
        self.pool = ThreadPoolExecutor(max_workers=workers, thread_name_prefix="bagmcp-work")
        self.deps: BagStoreDeps | None = None

    def ingest(self, bag_id: str) -> None:
        self.pool.submit(self._ingest, bag_id)

    def job(self, job_id: str) -> None:
        self.pool.submit(self._job, job_id)

    def _ingest(self, bag_id: str) -> None:
        assert self.deps is not None
        try:
            ingest_bag(self.deps, bag_id)
        except BagmcpError as err:
            log.warning("ingest of %s failed: %s", bag_id, err)

    def _job(self, job_id: str) -> None:
        assert self.deps is not None
        run_job(self.deps, job_id)


def default_index_root() -> Path:
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(os.environ.get("BAGMCP_INDEX_DIR", Path(base) / "bagmcp" / "index"))


def folder_deps(
    root: Path, *, index_root: Path | None = None, job_budget_s: float = 20.0
) -> tuple[BagStoreDeps, ThreadRunner]:
    """Embedded mode: a read-only folder, an in-memory catalog, work on a local thread pool.

    Every bag under ``root`` is catalogued now and ingested in the background; indexes are
    written under ``index_root`` (the folder itself is never written to).
    """
    runner = ThreadRunner()
    catalog = MemoryCatalog()
    deps = BagStoreDeps(
        catalog=catalog,
        files=FolderBagFiles(root, index_root or default_index_root()),
        jobs=MemoryJobStore(),
        submit_ingest=runner.ingest,
        submit_job=runner.job,
        job_budget_s=job_budget_s,
    )
    runner.deps = deps
    for bag_id in catalog_folder(catalog, root):
        deps.submit_ingest(bag_id)
    return deps, runner


def s3_store(settings: BagStoreSettings, *, wait_s: float = 60.0) -> S3Store:
    """The S3 store with its bucket; waits up to ``wait_s`` for a server that is still starting."""
    assert settings.s3 is not None
    s3 = settings.s3
    store = S3Store(
        endpoint=s3.endpoint,
        access_key=s3.access_key,
        secret_key=s3.secret_key,
        bucket=s3.bucket,
        secure=s3.secure,
    )
    deadline = time.monotonic() + wait_s
    while True:
        try:
            store.ensure_bucket()
            return store
        except StorageError as err:
            if time.monotonic() > deadline:
                raise
            log.warning("waiting for the object store: %s", err)
            time.sleep(1.0)


def team_deps(settings: BagStoreSettings, celery: Celery | None = None) -> BagStoreDeps:
    """Team mode: S3 for bags and indexes, Redis for the catalog, Celery for ingest."""
    assert settings.redis_url is not None
    store = s3_store(settings)
    app = celery or create_celery(settings.redis_url, visibility_timeout_s=settings.task_visibility_timeout_s)

    client = redis.Redis.from_url(settings.redis_url, socket_connect_timeout=3, socket_timeout=10)
    return BagStoreDeps(
        catalog=RedisCatalog(client),
        files=CachedBagFiles(store, settings.cache_dir, max_bytes=settings.cache_max_bytes),
        jobs=RedisJobStore(client),
        submit_ingest=lambda bag_id: _send(app, INGEST_TASK, bag_id),
        submit_job=lambda job_id: _send(app, JOB_TASK, job_id),
        store=store,
        max_result_bytes=settings.max_result_bytes,
        job_budget_s=settings.job_budget_s,
    )


def _send(app: Celery, task: str, argument: str) -> None:
    app.send_task(task, args=[argument])
