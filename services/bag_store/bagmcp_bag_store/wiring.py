"""Building the bag-store from the resources of a way of running (team or embedded)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from fastapi import APIRouter
from mcp.server.mcpserver import MCPServer

from bagmcp_bag_store.api import build_router
from bagmcp_bag_store.filtering import filter_bag
from bagmcp_bag_store.ingest.ingest import Ingestor
from bagmcp_bag_store.ingest.shelf import Shelf
from bagmcp_bag_store.ingest.upload import UploadPolicy
from bagmcp_bag_store.job_kinds import FILTER, INGEST, SEARCH
from bagmcp_bag_store.query.search import search_messages
from bagmcp_bag_store.settings import UploadSettings
from bagmcp_bag_store.tools import build_server
from bagmcp_kit.longwork import LongWork
from bagmcp_kit.server import Guard
from bagmcp_shared.jobs import JobRegistry
from bagmcp_shared.resources import Resources


@dataclass(frozen=True)
class BagStoreWork:
    """What runs in the background: ingest, and the jobs the registry knows."""

    shelf: Shelf
    ingestor: Ingestor
    registry: JobRegistry


def build_work(res: Resources) -> BagStoreWork:
    shelf = Shelf(res.catalog, res.store)
    ingestor = Ingestor(res.catalog, res.files, res.indexes, res.store)
    registry = JobRegistry()
    registry.add(
        SEARCH, lambda p, progress: search_messages(res.access, p, progress, budget_bytes=res.max_result_bytes)
    )
    registry.add(FILTER, lambda p, progress: filter_bag(res.access, shelf, ingestor, p, progress))
    return BagStoreWork(shelf, ingestor, registry)


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
    guard: Guard | None = None,
) -> BagStore:
    work = build_work(res)
    longwork = LongWork(res.jobs, res.runner, work.registry, budget_s=res.job_budget_s)
    server = build_server(res.access, longwork, budget_bytes=res.max_result_bytes, guard=guard)
    policy = UploadPolicy(
        shelf=work.shelf,
        queue_ingest=ingest_queue(res),
        upload_dir=res.scratch,
        max_bytes=uploads.max_bytes,
        archive_expansion=uploads.archive_expansion,
        stuck_after_s=uploads.stuck_after_s,
        uploads=res.uploads,
    )
    return BagStore(work, server, build_router(res.access, policy))
