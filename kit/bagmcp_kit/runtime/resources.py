"""What every service process is built from, for each way of running: the catalog, bag files and
index publishing, the job store, the background runner, object storage and bag access.

The composition root (a service's entry point, or the embedded command) builds one of these and
hands each function only the pieces it needs.
"""

from __future__ import annotations

import logging
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

from bagmcp_kit.runtime.sender import CeleryRunner
from bagmcp_shared.access import (
    BagAccess,
    BagFiles,
    FolderBagFiles,
    IndexPublisher,
    RangedBagFiles,
    ReaderCache,
)
from bagmcp_shared.budget import use_input_budget
from bagmcp_shared.catalog import Catalog, MemoryCatalog, RedisCatalog
from bagmcp_shared.errors import StorageError
from bagmcp_shared.jobs import JobStore, MemoryJobStore, RedisJobStore
from bagmcp_shared.redis_connection import redis_client, wait_for_redis
from bagmcp_shared.scratch import use_scratch
from bagmcp_shared.settings import (
    DEFAULT_INPUT_BUDGET,
    DEFAULT_OPEN_BAGS,
    InputBudget,
    OpenBagLimits,
    S3Settings,
    TeamSettings,
)
from bagmcp_shared.storage import LocalStore, ObjectStore, S3Store
from bagmcp_shared.tasks import Runner, ThreadRunner
from bagmcp_shared.worker_counters import WorkerSums

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class Resources:
    """``store`` is where new bags and artifacts go; ``uploads`` False refuses REST uploads; ``scratch`` is
    this process's directory for temporary files."""

    catalog: Catalog
    files: BagFiles
    indexes: IndexPublisher
    job_store: JobStore
    runner: Runner
    store: ObjectStore
    access: BagAccess
    scratch: Path
    uploads: bool = True
    max_result_bytes: int = 16_000
    job_budget_s: float = 20.0
    worker_sums: WorkerSums | None = None  # team mode: the counters of this service's workers, in Redis

    def counters(self) -> dict[str, int]:
        """This process's counters: block cache hits and misses and bytes fetched from S3 (none when bags are
        read from a folder)."""
        return self.files.counters.snapshot() if isinstance(self.files, RangedBagFiles) else {}

    def metrics(self) -> dict[str, dict[str, int] | None]:
        """For /metrics, by process: ``service`` (this one's counters) and ``workers`` (the sums of this
        service's workers, each counter 0 until one counts it; None while Redis is unreachable)."""
        own = self.counters()
        if self.worker_sums is None:
            return {"service": own}
        sums = self.worker_sums.read()
        return {"service": own, "workers": None if sums is None else {name: sums.get(name, 0) for name in own}}


@dataclass(frozen=True)
class Embedded:
    resources: Resources
    runner: ThreadRunner
    folder: Path
    data_dir: Path


def embedded_resources(
    folder: Path,
    data_dir: Path,
    *,
    job_budget_s: float = 20.0,
    open_bags: OpenBagLimits = DEFAULT_OPEN_BAGS,
    input_budget: InputBudget = DEFAULT_INPUT_BUDGET,
) -> Embedded:
    """One process over a read-only folder: memory catalog and jobs, a thread runner, indexes and
    the bags and artifacts the server makes under ``data_dir``; ``input_budget`` becomes the process's."""
    use_input_budget(input_budget)
    store = LocalStore(data_dir / "store")
    files = FolderBagFiles(folder, data_dir / "index", store)
    catalog = MemoryCatalog()
    jobs = MemoryJobStore()
    runner = ThreadRunner()
    runner.on_shutdown(jobs.cancel_unfinished)
    cache = ReaderCache(open_bags)
    runner.on_shutdown(cache.close)
    resources = Resources(
        catalog=catalog,
        files=files,
        indexes=files,
        job_store=jobs,
        runner=runner,
        store=store,
        access=BagAccess(catalog, files, cache=cache),
        scratch=Path(tempfile.gettempdir()),
        uploads=False,
        job_budget_s=job_budget_s,
    )
    return Embedded(resources, runner, folder, data_dir)


def s3_store(settings: S3Settings, *, wait_s: float = 60.0) -> S3Store:
    """The S3 store with its bucket; waits up to ``wait_s`` for a server that is still starting."""
    store = S3Store(
        endpoint=settings.endpoint,
        access_key=settings.access_key,
        secret_key=settings.secret_key,
        bucket=settings.bucket,
        secure=settings.secure,
        read_timeout_s=settings.read_timeout_s,
        ca_file=settings.ca_file,
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


def team_resources(settings: TeamSettings, *, queue: str) -> Resources:
    """Team mode: S3 for bags, indexes and artifacts, Redis for the catalog and jobs, Celery for work; this
    process's temporary files in its scratch directory under the data directory; the settings' input
    budget becomes the process's."""
    use_input_budget(settings.input_budget)
    scratch = use_scratch(settings.scratch_dir)
    store = s3_store(settings.s3)
    client = redis_client(settings.redis_url)
    wait_for_redis(client)
    files = RangedBagFiles(store, settings.cache_dir, max_bytes=settings.cache_max_bytes, reads=settings.range_reads)
    catalog = RedisCatalog(client)
    return Resources(
        catalog=catalog,
        files=files,
        indexes=files,
        job_store=RedisJobStore(client),
        runner=CeleryRunner(settings.redis_url, queue=queue, visibility_timeout_s=settings.task_visibility_timeout_s),
        store=store,
        access=BagAccess(catalog, files, cache=ReaderCache(settings.open_bags)),
        scratch=scratch,
        max_result_bytes=settings.max_result_bytes,
        job_budget_s=settings.job_budget_s,
        worker_sums=WorkerSums(client, queue),
    )
