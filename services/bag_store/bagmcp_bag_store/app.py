"""``create_app``: the bag-store service in team mode, on the kit's service app."""

from __future__ import annotations

from fastapi import FastAPI

from bagmcp_bag_store.errors import STATUSES
from bagmcp_bag_store.fleet.backfill import queue_fleet_backfill
from bagmcp_bag_store.ingest.rebuild import RESTORE_WAIT_S, restore_lost_catalog
from bagmcp_bag_store.settings import BagStoreSettings
from bagmcp_bag_store.task_refs import QUEUE
from bagmcp_bag_store.wiring import build_bag_store, ingest_queue
from bagmcp_kit.runtime.resources import team_resources
from bagmcp_kit.server import McpGuard
from bagmcp_kit.service_app import create_service_app
from bagmcp_shared.storage import S3Store


def create_app(settings: BagStoreSettings) -> FastAPI:
    """The service over Redis and S3; a catalog lost with Redis's data is rebuilt from storage first, and
    ready bags missing from the columnar store are queued to feed it."""
    service = settings.service
    resources = team_resources(service.team, queue=QUEUE)
    restore_lost_catalog(resources.catalog, resources.store, ingest_queue(resources), wait_s=RESTORE_WAIT_S)
    queue_fleet_backfill(resources.catalog, ingest_queue(resources))
    bag_store = build_bag_store(
        resources, uploads=settings.uploads, queries=settings.queries, guard=McpGuard.of(service)
    )
    return create_service_app(
        title="bagmcp bag-store",
        server=bag_store.server,
        routers=[bag_store.router],
        service_token=service.team.service_token,
        allowed_hosts=service.http.allowed_hosts,
        statuses=STATUSES,
        checks={"s3": resources.store.answers} if isinstance(resources.store, S3Store) else None,
        metrics=resources.metrics,
    )
