"""Building the bag-store from the resources of a way of running (team or embedded)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from fastapi import APIRouter
from mcp.server.mcpserver import MCPServer

from bagmcp_bag_store.api import build_router
from bagmcp_bag_store.fleet.routes import build_query_router
from bagmcp_bag_store.fleet.service import build_fleet
from bagmcp_bag_store.ingest.ingest import Ingestor
from bagmcp_bag_store.ingest.shelf import Shelf
from bagmcp_bag_store.ingest.upload import UploadPolicy
from bagmcp_bag_store.settings import QueryLimits, UploadSettings
from bagmcp_bag_store.task_refs import INGEST
from bagmcp_bag_store.tools import BAG_STORE, build_server
from bagmcp_bag_store.tools.store import Store
from bagmcp_kit.longwork import LongWork
from bagmcp_kit.runtime.resources import Resources
from bagmcp_kit.server import McpGuard
from bagmcp_shared.jobs import JobRegistry


@dataclass(frozen=True)
class BagStoreWork:
    """What runs in the background: ingest, and the jobs the registry knows (the fleet's queries too)."""

    store: Store
    registry: JobRegistry


def build_work(res: Resources, *, queries: QueryLimits | None = None) -> BagStoreWork:
    shelf = Shelf(res.catalog, res.store)
    ingestor = Ingestor(res.catalog, res.files, res.indexes, res.store)
    fleet = build_fleet(
        res.catalog, res.store, res.files, limits=queries or QueryLimits(), budget_bytes=res.max_result_bytes
    )
    store = Store(res.access, shelf, ingestor, fleet, res.max_result_bytes)
    return BagStoreWork(store, BAG_STORE.registry(store))


def ingest_queue(res: Resources) -> Callable[[str], None]:
    """Queue a bag's ingest where this way of running does it (a Celery worker, or a thread)."""
    return lambda bag_id: res.runner.submit(INGEST, bag_id)


@dataclass(frozen=True)
class BagStore:
    work: BagStoreWork
    server: MCPServer
    router: APIRouter


def build_bag_store(
    res: Resources,
    *,
    uploads: UploadSettings,
    queries: QueryLimits | None = None,
    guard: McpGuard | None = None,
) -> BagStore:
    work = build_work(res, queries=queries)
    longwork = LongWork(res.job_store, res.runner, work.registry, budget_s=res.job_budget_s)
    server = build_server(work.store, longwork, guard=guard)
    policy = UploadPolicy(
        shelf=work.store.shelf,
        queue_ingest=ingest_queue(res),
        upload_dir=res.scratch,
        max_bytes=uploads.max_bytes,
        archive_expansion=uploads.archive_expansion,
        stuck_after_s=uploads.stuck_after_s,
        uploads=res.uploads,
    )
    routers = APIRouter()
    routers.include_router(build_router(res.access, policy, forget=work.store.fleet.engine.forget))
    routers.include_router(build_query_router(work.store.fleet))
    return BagStore(work, server, routers)
