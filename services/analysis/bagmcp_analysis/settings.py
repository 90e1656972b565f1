"""Analysis settings, read once at the entry point and passed down."""

from __future__ import annotations

from bagmcp_shared.settings import Env, ServiceSettings

DEFAULT_PORT = 8002


def analysis_settings(env: Env | None = None) -> ServiceSettings:
    """Team mode: Redis + S3 + a service token, all from ``BAGMCP_*`` variables."""
    return ServiceSettings.from_env(env or Env(), name="analysis", port=DEFAULT_PORT)
