"""/readyz says ready only once calls can reach every upstream's tools: a listing round sets each upstream's
state as it answers and builds the routes when all have, and a stack's first call right after its /readyz
once answered "Unknown tool: list_bags (services unavailable right now: none)" from that gap."""

from __future__ import annotations

import httpx
import pytest
from fastapi import FastAPI
from mcp.server.subscriptions import InMemorySubscriptionBus

from bagmcp_gateway.mcp_front.metrics import GatewayMetrics
from bagmcp_gateway.rest_front.health import readiness_router
from bagmcp_gateway.upstreams.connections import Connections
from bagmcp_gateway.upstreams.tool_catalog import ToolCatalog
from tests.fixtures.inprocess import InProcess

pytestmark = pytest.mark.anyio


async def _ready(app: FastAPI) -> int:
    async with httpx.AsyncClient(transport=httpx.ASGITransport(app=app), base_url="http://gateway") as client:
        return (await client.get("/readyz")).status_code


async def test_readyz_waits_for_the_routes_of_a_listing_round(served_small: InProcess) -> None:
    upstreams = served_small.composition.upstreams
    catalog = ToolCatalog(upstreams, Connections(upstreams), InMemorySubscriptionBus())
    app = FastAPI()
    app.include_router(readiness_router(catalog, GatewayMetrics(), None))
    for upstream in upstreams:  # every upstream has answered; the round has not built its routes yet
        await catalog.refresh(upstream)
    assert all(state.up for state in catalog.states.values())
    assert "list_bags" not in catalog.routes
    assert await _ready(app) == 503
    await catalog.refresh_all()
    assert "list_bags" in catalog.routes
    assert await _ready(app) == 200
