"""Bag-store settings, read once at the entry point (``BagStoreSettings.from_env``) and passed down."""

from __future__ import annotations

from dataclasses import dataclass

from bagmcp_shared.settings import Env, ServiceSettings

DEFAULT_PORT = 8001
DEFAULT_MAX_UPLOAD_BYTES = 50 * 2**30


@dataclass(frozen=True)
class UploadSettings:
    """``max_bytes`` bounds an upload and what an archive unpacks to (also at most ``archive_expansion``
    times the archive); a re-upload of a bag still ingesting ``stuck_after_s`` after it was queued (or
    failed) queues its ingest again."""

    max_bytes: int = DEFAULT_MAX_UPLOAD_BYTES
    archive_expansion: int = 20
    stuck_after_s: float = 120.0


@dataclass(frozen=True)
class QueryLimits:
    """Queries across bags (query_bags, find_bags, GET /api/v1/query): ``timeout_s``, ``memory_mb`` and
    ``threads`` bound each query; ``max_rows`` is what a tool answer shows (``rest_max_rows`` a REST download);
    ``cache_bytes`` bounds the views' rows each process keeps in memory."""

    timeout_s: float = 10.0
    memory_mb: int = 1024
    threads: int = 2
    max_rows: int = 200
    rest_max_rows: int = 100_000
    cache_bytes: int = 2 * 2**30

    @classmethod
    def from_env(cls, env: Env) -> QueryLimits:
        return cls(
            timeout_s=env.number("BAGMCP_QUERY_TIMEOUT_S", 10.0),
            memory_mb=env.integer("BAGMCP_QUERY_MEMORY_MB", 1024),
            threads=env.integer("BAGMCP_QUERY_THREADS", 2),
            max_rows=env.integer("BAGMCP_QUERY_MAX_ROWS", 200),
            rest_max_rows=env.integer("BAGMCP_QUERY_REST_MAX_ROWS", 100_000),
            cache_bytes=env.integer("BAGMCP_QUERY_CACHE_BYTES", 2 * 2**30),
        )


DEFAULT_QUERY_LIMITS = QueryLimits()


@dataclass(frozen=True)
class BagStoreSettings:
    service: ServiceSettings
    uploads: UploadSettings
    queries: QueryLimits = DEFAULT_QUERY_LIMITS

    @classmethod
    def from_env(cls, env: Env | None = None) -> BagStoreSettings:
        """Team mode: Redis + S3 + a service token, all from ``BAGMCP_*`` variables."""
        env = env or Env()
        service = ServiceSettings.from_env(env, name="bag-store", port=DEFAULT_PORT)
        uploads = UploadSettings(
            max_bytes=env.integer("BAGMCP_MAX_UPLOAD_BYTES", DEFAULT_MAX_UPLOAD_BYTES),
            archive_expansion=env.integer("BAGMCP_ARCHIVE_MAX_EXPANSION", 20),
            stuck_after_s=env.number("BAGMCP_INGEST_STUCK_AFTER_S", 120.0),
        )
        return cls(service=service, uploads=uploads, queries=QueryLimits.from_env(env))
