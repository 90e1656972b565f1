"""At start-up: every ready bag whose index lacks the views' files (ingested before they existed, or their
writing failed) gets its ingest queued again, which only adds those files to its index (from the index)."""

from __future__ import annotations

import logging
from collections.abc import Callable

from bagmcp_bag_store.fleet.files import has_views
from bagmcp_shared.catalog import Catalog

log = logging.getLogger(__name__)


def queue_fleet_backfill(catalog: Catalog, queue_ingest: Callable[[str], None]) -> list[str]:
    """Queue the ready bags without their views' files; returns their ids."""
    missing = [r.id for r in catalog.all() if r.status == "ready" and not has_views(r)]
    for bag_id in missing:
        queue_ingest(bag_id)
    if missing:
        log.info("queued %d bags to add their views to their index", len(missing))
    return missing
