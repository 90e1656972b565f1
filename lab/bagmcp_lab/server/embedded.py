"""The Lab inside ``bagmcp serve``: its routes join the server's REST routes (behind the same token check),
and its agent loops reach the server's own /mcp through an in-process ASGI transport (no socket, no second
server), with the caller's token so the caller's profile applies as it does over HTTP."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import httpx2
from fastapi import APIRouter, FastAPI

from bagmcp_lab.server.routes import LAB_STATUSES, build_lab_router
from bagmcp_lab.server.service import LabService, McpTarget
from bagmcp_lab.settings import LabSettings
from bagmcp_shared.errors import BagmcpError


@dataclass
class LabInProcess:
    service: LabService
    router: APIRouter
    statuses: Sequence[tuple[type[BagmcpError], int, str]]
    app: FastAPI | None = None

    def attach(self, app: FastAPI) -> None:
        self.app = app

    def transport(self) -> httpx2.AsyncBaseTransport:
        assert self.app is not None, "attach the app before serving"
        return httpx2.ASGITransport(app=self.app)


def lab_in_process(settings: LabSettings, *, port: int) -> LabInProcess:
    """``port``: the server's own, for the Host header the in-process calls carry (a loopback name it accepts)."""
    service = LabService(settings, McpTarget(f"http://127.0.0.1:{port}/mcp"))
    lab = LabInProcess(service, build_lab_router(service), LAB_STATUSES)
    service.target.transport = lab.transport
    return lab
