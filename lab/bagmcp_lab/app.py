"""The Lab as a service of its own (team mode): its routes behind the service credential (only the gateway
calls it, forwarding each caller's token in ``x-bagmcp-caller``), its agent loops calling the gateway's MCP
endpoint with that token, never the service credential."""

from __future__ import annotations

import contextlib
from collections.abc import AsyncIterator

from fastapi import FastAPI

from bagmcp_kit.auth import rest_guard
from bagmcp_kit.service_app import new_app
from bagmcp_lab.server.routes import LAB_STATUSES, build_lab_router
from bagmcp_lab.server.service import CALLER_HEADER, LabService, McpTarget
from bagmcp_lab.settings import LabServiceSettings


def create_app(settings: LabServiceSettings) -> FastAPI:
    service = LabService(settings.lab, McpTarget(settings.gateway_mcp_url), caller_header=CALLER_HEADER)

    @contextlib.asynccontextmanager
    async def lifespan(_app: FastAPI) -> AsyncIterator[None]:
        yield

    return new_app(
        title="bagmcp lab",
        lifespan=lifespan,
        routers=[build_lab_router(service)],
        guard=rest_guard(settings.service_token),
        allowed_hosts=settings.http.allowed_hosts,
        statuses=LAB_STATUSES,
    )
