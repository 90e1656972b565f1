"""What the bag-store's functions need, bundled once at start-up and passed down."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from bagmcp_bag_store.bagfiles import BagFiles
from bagmcp_bag_store.catalog import Catalog
from bagmcp_bag_store.jobs import JobStore
from bagmcp_shared.storage import ObjectStore

Submitter = Callable[[str], None]


@dataclass(frozen=True)
class BagStoreDeps:
    """``store`` is where new bags go (uploads, filter_bag); ``uploads`` False refuses REST uploads.

    ``submit_ingest`` and ``submit_job`` hand a bag id / job id to whatever runs background work
    (Celery in team mode, a thread pool when embedded). ``job_budget_s`` is how long a tool waits
    for its job before answering with the job id instead.
    """

    catalog: Catalog
    files: BagFiles
    jobs: JobStore
    submit_ingest: Submitter
    submit_job: Submitter
    store: ObjectStore | None = None
    uploads: bool = True
    max_result_bytes: int = 16_000
    job_budget_s: float = 20.0
