"""Building the bag-store's dependencies for each way of running it."""

from __future__ import annotations

import logging
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

from celery import Celery

from bagmcp_bag_store.bagfiles import CachedBagFiles, FolderBagFiles
from bagmcp_bag_store.catalog import MemoryCatalog, RedisCatalog
from bagmcp_bag_store.deps import BagStoreDeps
from bagmcp_bag_store.folder import catalog_folder
from bagmcp_bag_store.ingest import ingest_bag
from bagmcp_bag_store.settings import BagStoreSettings
from bagmcp_bag_store.tasks import INGEST_TASK, create_celery
from bagmcp_shared.errors import BagmcpError, StorageError
from bagmcp_shared.storage import S3Store

log = logging.getLogger(__name__)


def folder_deps(root: Path, *, workers: int = 2) -> tuple[BagStoreDeps, ThreadPoolExecutor]:
    """Embedded mode: a read-only folder, an in-memory catalog, ingest on a local thread pool.

    Every bag under ``root`` is catalogued now and ingested in the background.
    """
    catalog = MemoryCatalog()
    pool = ThreadPoolExecutor(max_workers=workers, thread_name_prefix="ingest")
    deps_box: list[BagStoreDeps] = []

    def run(bag_id: str) -> None:
        try:
            ingest_bag(deps_box[0], bag_id)
        except BagmcpError as err:
            log.warning("ingest of %s failed: %s", bag_id, err)

    deps = BagStoreDeps(
        catalog=catalog, files=FolderBagFiles(root), submit_ingest=lambda i: _submit(pool, run, i)
    )
    deps_box.append(deps)
    for bag_id in catalog_folder(catalog, root):
        deps.submit_ingest(bag_id)
    return deps, pool


def _submit(pool: ThreadPoolExecutor, run: object, bag_id: str) -> None:
    assert callable(run)
    pool.submit(run, bag_id)


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
    app = celery or create_celery(settings.redis_url)

    def submit(bag_id: str) -> None:
        app.send_task(INGEST_TASK, args=[bag_id])

    return BagStoreDeps(
        catalog=RedisCatalog.from_url(settings.redis_url),
        files=CachedBagFiles(store, settings.cache_dir, max_bytes=settings.cache_max_bytes),
        submit_ingest=submit,
        store=store,
        max_result_bytes=settings.max_result_bytes,
    )
