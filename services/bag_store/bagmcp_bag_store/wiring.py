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
from bagmcp_bag_store.catalog_memory import MemoryCatalog
from bagmcp_bag_store.catalog_redis import RedisCatalog
from bagmcp_bag_store.deps import BagStoreDeps
from bagmcp_bag_store.folder import catalog_folder, catalog_stored
from bagmcp_bag_store.ingest import ingest_bag, mark_failed
from bagmcp_bag_store.jobrun import run_job
from bagmcp_bag_store.jobs import MemoryJobStore, RedisJobStore
from bagmcp_bag_store.settings import BagStoreSettings
from bagmcp_bag_store.tasks import INGEST_TASK, JOB_TASK, create_celery
from bagmcp_shared.errors import StorageError
from bagmcp_shared.storage import LocalStore, S3Store

log = logging.getLogger(__name__)


class ThreadRunner:
    """Background work inside this process (embedded mode): ingest and jobs on separate thread pools,
    so a search never waits behind start-up ingest."""

    def __init__(self, *, ingest_workers: int = 1, job_workers: int = 2) -> None:
        self._ingest_pool = ThreadPoolExecutor(max_workers=ingest_workers, thread_name_prefix="bagmcp-ingest")
        self._job_pool = ThreadPoolExecutor(max_workers=job_workers, thread_name_prefix="bagmcp-job")
        self._jobs: set[str] = set()
        self.deps: BagStoreDeps | None = None

    def ingest(self, bag_id: str) -> None:
        self._ingest_pool.submit(self._ingest, bag_id)

    def job(self, job_id: str) -> None:
        self._jobs.add(job_id)
        self._job_pool.submit(self._job, job_id)

    def _ingest(self, bag_id: str) -> None:
        assert self.deps is not None
        try:
            ingest_bag(self.deps, bag_id)
        except Exception as err:  # a thread has no caller to report to: record it on the bag
            log.exception("ingest of %s failed", bag_id)
            mark_failed(self.deps, bag_id, f"ingest failed ({type(err).__name__}: {err})")

    def _job(self, job_id: str) -> None:
        assert self.deps is not None
        run_job(self.deps, job_id)

    def shutdown(self) -> None:
        """Stop taking work, ask running jobs to stop, and drop what has not started."""
        if self.deps is not None:
            for job_id in self._jobs:
                self.deps.jobs.request_cancel(job_id)
        for pool in (self._ingest_pool, self._job_pool):
            pool.shutdown(wait=False, cancel_futures=True)


def default_data_dir() -> Path:
    """Where an embedded server keeps indexes and the bags it makes (never inside the served folder)."""
    cache = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(os.environ.get("BAGMCP_DATA_DIR") or Path(cache) / "bagmcp")


def folder_deps(
    root: Path, *, data_dir: Path | None = None, job_budget_s: float = 20.0
) -> tuple[BagStoreDeps, ThreadRunner]:
    """Embedded mode: the served folder (read-only), an in-memory catalog, work on a thread pool.

    Every bag under ``root`` is catalogued now and ingested in the background. Indexes and the
    bags filter_bag writes go under ``data_dir``; REST uploads are refused.
    """
    data = data_dir or default_data_dir()
    store = LocalStore(data / "store")
    runner = ThreadRunner()
    catalog = MemoryCatalog()
    deps = BagStoreDeps(
        catalog=catalog,
        files=FolderBagFiles(root, data / "index", store),
        jobs=MemoryJobStore(),
        submit_ingest=runner.ingest,
        submit_job=runner.job,
        store=store,
        uploads=False,
        job_budget_s=job_budget_s,
    )
    runner.deps = deps
    for bag_id in [*catalog_folder(catalog, root, id_cache=data / "content-ids.json"), *catalog_stored(catalog, store)]:
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
        read_timeout_s=s3.read_timeout_s,
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
