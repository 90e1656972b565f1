"""What runs while the gateway serves: the shared change-event bus (team mode), the upstream links, the tool
tool catalog (listed once before the first request, then kept fresh) and the MCP session manager; on the way out
the audit log is flushed and ``on_shutdown`` runs (embedded mode closes its services there)."""

from __future__ import annotations

import contextlib
from collections.abc import AsyncIterator, Callable
from contextlib import AbstractAsyncContextManager
from typing import Any

import anyio
from fastapi import FastAPI
from mcp.server import Server

from bagmcp_gateway.mcp_front.gateway import Gateway
from bagmcp_gateway.upstreams.change_events import RedisSubscriptionBus

Lifespan = Callable[[FastAPI], AbstractAsyncContextManager[None]]


def gateway_lifespan(
    gateway: Gateway,
    server: Server[Any],
    *,
    shared_bus: RedisSubscriptionBus | None,
    on_shutdown: Callable[[], None] | None = None,
) -> Lifespan:
    tool_catalog = gateway.tool_catalog

    @contextlib.asynccontextmanager
    async def lifespan(_app: FastAPI) -> AsyncIterator[None]:
        async with anyio.create_task_group() as group:
            if shared_bus is not None:
                await group.start(shared_bus.run)
            await group.start(gateway.connections.run)
            await tool_catalog.refresh_all()
            tool_catalog.check_startup()  # a tool name two upstreams publish stops the gateway here, naming both
            gateway.listed = True
            await group.start(tool_catalog.run)
            async with server.session_manager.run():
                yield
            group.cancel_scope.cancel()
        if gateway.audit is not None:
            gateway.audit.close()
        if on_shutdown is not None:
            on_shutdown()

    return lifespan
