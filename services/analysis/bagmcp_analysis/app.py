"""``create_app``: the analysis service in team mode, on the kit's service app."""

from __future__ import annotations

from fastapi import FastAPI

from bagmcp_analysis.task_refs import QUEUE
from bagmcp_analysis.wiring import build_analysis
from bagmcp_kit.runtime.resources import team_resources
from bagmcp_kit.server import McpGuard
from bagmcp_kit.service_app import create_service_app
from bagmcp_shared.settings import ServiceSettings


def create_app(settings: ServiceSettings) -> FastAPI:
    resources = team_resources(settings.team, queue=QUEUE)
    server, _ = build_analysis(resources, guard=McpGuard.of(settings))
    return create_service_app(
        title="bagmcp analysis",
        server=server,
        service_token=settings.team.service_token,
        allowed_hosts=settings.http.allowed_hosts,
        metrics=resources.metrics,
    )
