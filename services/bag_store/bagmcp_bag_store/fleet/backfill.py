"""At start-up: every ready bag whose columnar store's files are missing (ingested before that store existed,
or its write failed) gets its ingest queued again, which writes only those files (from the stored index)."""

from __future__ import annotations

import logging
from collections.abc import Callable

from bagmcp_bag_store.fleet.files import FleetFiles
from bagmcp_shared.catalog import Catalog
from bagmcp_shared.storage import ObjectStore

log = logging.getLogger(__name__)


def queue_fleet_backfill(catalog: Catalog, store: ObjectStore, queue_ingest: Callable[[str], None]) -> list[str]:
    """Queue the ready bags without their files (one listing of the store); returns their ids."""
    stored = FleetFiles(store).stored_ids()
    missing = [r.id for r in catalog.all() if r.status == "ready" and r.id not in stored]
    for bag_id in missing:
        queue_ingest(bag_id)
    if missing:
        log.info("queued %d bags to feed the columnar store", len(missing))
    return missing
