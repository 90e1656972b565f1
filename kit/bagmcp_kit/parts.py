"""What a service contributes when every service runs in one process (the embedded command)."""

from __future__ import annotations

from dataclasses import dataclass, field

from fastapi import APIRouter
from mcp.server.mcpserver import MCPServer

from bagmcp_kit.http_errors import StatusTable


@dataclass(frozen=True)
class ServicePart:
    """``name`` is the upstream name the gateway shows in errors and /readyz (``[a-z][a-z0-9-]*``)."""

    name: str
    server: MCPServer
    routers: tuple[APIRouter, ...] = ()
    statuses: StatusTable = field(default_factory=tuple)
