"""Bag-store settings, read once at the entry point and passed down."""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

from bagmcp_shared.errors import BagmcpError

PLACEHOLDER_SECRETS = {"", "changeme", "change-me", "secret"}


class SettingsError(BagmcpError):
    """A setting is missing or unsafe; the service refuses to start."""


@dataclass(frozen=True)
class S3Settings:
    endpoint: str
    access_key: str
    secret_key: str
    bucket: str
    secure: bool = False
    read_timeout_s: float = 60.0


@dataclass(frozen=True)
class BagStoreSettings:
    """Everything the bag-store needs. ``s3`` None means local-directory storage (embedded)."""

    data_dir: Path
    redis_url: str | None = None
    s3: S3Settings | None = None
    service_token: str | None = None
    cache_max_bytes: int = 20 * 2**30
    max_upload_bytes: int = 50 * 2**30
    max_result_bytes: int = 16_000
    job_budget_s: float = 20.0
    task_visibility_timeout_s: int = 3600
    allowed_hosts: tuple[str, ...] = ("127.0.0.1:*", "localhost:*", "bag-store:*", "bag_store:*")

    @property
    def cache_dir(self) -> Path:
        return self.data_dir / "cache"

    @property
    def upload_dir(self) -> Path:
        return self.data_dir / "uploads"

    @classmethod
    def from_env(cls, env: dict[str, str] | None = None) -> BagStoreSettings:
        """Distributed mode: Redis + S3 + a service token, all from ``BAGMCP_*`` variables."""
        env = dict(os.environ) if env is None else env

        def need(key: str) -> str:
            value = env.get(key, "")
            if not value:
                raise SettingsError(f"{key} must be set")
            return value

        token = need("BAGMCP_SERVICE_TOKEN")
        secret = need("BAGMCP_S3_SECRET_KEY")
        if token.lower() in PLACEHOLDER_SECRETS or secret.lower() in PLACEHOLDER_SECRETS:
            raise SettingsError("BAGMCP_SERVICE_TOKEN and BAGMCP_S3_SECRET_KEY must not be placeholders")
        s3 = S3Settings(
            endpoint=need("BAGMCP_S3_ENDPOINT"),
            access_key=need("BAGMCP_S3_ACCESS_KEY"),
            secret_key=secret,
            bucket=env.get("BAGMCP_S3_BUCKET", "bagmcp"),
            secure=env.get("BAGMCP_S3_SECURE", "false").lower() == "true",
            read_timeout_s=float(env.get("BAGMCP_S3_READ_TIMEOUT_S", 60.0)),
        )
        return cls(
            data_dir=Path(env.get("BAGMCP_DATA_DIR", "/var/lib/bagmcp")),
            redis_url=need("BAGMCP_REDIS_URL"),
            s3=s3,
            service_token=token,
            cache_max_bytes=int(env.get("BAGMCP_CACHE_MAX_BYTES", 20 * 2**30)),
            max_upload_bytes=int(env.get("BAGMCP_MAX_UPLOAD_BYTES", 50 * 2**30)),
            job_budget_s=float(env.get("BAGMCP_JOB_BUDGET_S", 20.0)),
            task_visibility_timeout_s=int(env.get("BAGMCP_TASK_VISIBILITY_TIMEOUT_S", 3600)),
        )
