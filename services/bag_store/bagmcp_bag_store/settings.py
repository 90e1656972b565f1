"""Bag-store settings, read once at the entry point (``BagStoreSettings.from_env``) and passed down."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from bagmcp_shared.settings import Env, ServiceSettings

DEFAULT_PORT = 8001


@dataclass(frozen=True)
class BagStoreSettings:
    service: ServiceSettings
    max_upload_bytes: int = 50 * 2**30

    @classmethod
    def from_env(cls, env: Env | None = None) -> BagStoreSettings:
        """Team mode: Redis + S3 + a service token, all from ``BAGMCP_*`` variables."""
        env = env or Env()
        return cls(
            service=ServiceSettings.from_env(env, name="bag-store", port=DEFAULT_PORT),
            max_upload_bytes=env.integer("BAGMCP_MAX_UPLOAD_BYTES", 50 * 2**30),
        )

    @property
    def upload_dir(self) -> Path:
        return self.service.team.data_dir / "uploads"
