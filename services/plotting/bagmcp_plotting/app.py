"""``create_app``: the plotting service in team mode, on the kit's service app."""

from __future__ import annotations

from fastapi import FastAPI

from bagmcp_kit.runtime.resources import team_resources
from bagmcp_kit.server import McpGuard
from bagmcp_kit.service_app import create_service_app
from bagmcp_plotting.settings import PlottingSettings
from bagmcp_plotting.task_refs import QUEUE
from bagmcp_plotting.wiring import build_plotting


def create_app(settings: PlottingSettings) -> FastAPI:
    service = settings.service
    resources = team_resources(service.team, queue=QUEUE)
    server, router, _ = build_plotting(
        resources, artifact_base_url=settings.artifact_base_url, guard=McpGuard.of(service)
    )
    return create_service_app(
        title="bagmcp plotting",
        server=server,
        routers=[router],
        service_token=service.team.service_token,
        allowed_hosts=service.http.allowed_hosts,
        metrics=resources.metrics,
    )
