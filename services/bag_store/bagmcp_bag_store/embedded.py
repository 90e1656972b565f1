"""The bag-store inside one process (``bagmcp serve`` / ``stdio``): a read-only folder of bags,
catalogued at start-up and ingested on a thread pool; jobs on another pool."""

from __future__ import annotations

import logging

from bagmcp_bag_store.errors import STATUSES
from bagmcp_bag_store.ingest.folder import FolderHashes, catalog_folder
from bagmcp_bag_store.ingest.rebuild import rebuild_catalog
from bagmcp_bag_store.settings import QueryLimits, UploadSettings
from bagmcp_bag_store.task_refs import INGEST, RUN_JOB
from bagmcp_bag_store.wiring import BagStore, build_bag_store
from bagmcp_kit.parts import ServicePart
from bagmcp_kit.runtime.resources import Embedded
from bagmcp_shared.jobs import run_job

log = logging.getLogger(__name__)


def start_embedded(embedded: Embedded, *, queries: QueryLimits | None = None) -> BagStore:
    """The bag-store over the embedded resources; starts cataloguing and ingesting the folder (ingest feeds
    the columnar store every bag it lacks, from the bag's index when that is reused)."""
    res = embedded.resources
    bag_store = build_bag_store(res, uploads=UploadSettings(max_bytes=0), queries=queries)
    work = bag_store.work

    hashes = FolderHashes(res.catalog, embedded.folder, embedded.data_dir / "content-ids.json")

    def ingest(bag_id: str) -> None:
        try:
            hashes.fill(bag_id)
            if work.store.ingestor.ingest(bag_id) == "ready":
                res.access.warm(bag_id)  # this process answers the questions: keep the bag open for the first
        except Exception as err:  # a thread has no caller to report to: record it on the bag
            log.exception("ingest of %s failed", bag_id)
            work.store.ingestor.mark_failed(bag_id, f"ingest failed ({type(err).__name__}: {err})")

    embedded.runner.bind(INGEST, ingest, workers=1)
    embedded.runner.bind(RUN_JOB, lambda job_id: run_job(work.registry, res.job_store, job_id), workers=2)
    ids = catalog_folder(res.catalog, embedded.folder)
    made_here = rebuild_catalog(res.catalog, res.store, summaries=False).to_ingest  # the bags filter_bag made
    for bag_id in [*ids, *made_here]:
        res.runner.submit(INGEST, bag_id)
    return bag_store


def embedded_part(embedded: Embedded, *, queries: QueryLimits | None = None) -> ServicePart:
    """The bag-store part of the embedded server."""
    bag_store = start_embedded(embedded, queries=queries)
    return ServicePart("bag-store", bag_store.server, (bag_store.router,), STATUSES)
