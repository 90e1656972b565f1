"""Plotting settings, read once at the entry point and passed down."""

from __future__ import annotations

from dataclasses import dataclass

from bagmcp_shared.settings import Env, ServiceSettings

DEFAULT_PORT = 8003


@dataclass(frozen=True)
class PlottingSettings:
    """``artifact_base_url`` is where callers reach the REST API (the gateway's public URL)."""

    service: ServiceSettings
    artifact_base_url: str = ""

    @classmethod
    def from_env(cls, env: Env | None = None) -> PlottingSettings:
        env = env or Env()
        return cls(
            service=ServiceSettings.from_env(env, name="plotting", port=DEFAULT_PORT),
            artifact_base_url=env.text("BAGMCP_ARTIFACT_BASE_URL", ""),
        )
