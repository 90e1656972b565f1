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
class BagStoreSettings:
    service: ServiceSettings
    uploads: UploadSettings

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
        return cls(service=service, uploads=uploads)
