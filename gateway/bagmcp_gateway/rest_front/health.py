"""/readyz (public: up or down, no reasons) and /metrics (admin scope) of the gateway."""

from __future__ import annotations

import redis
from fastapi import APIRouter
from fastapi.responses import JSONResponse, Response

from bagmcp_gateway.mcp_front.metrics import GatewayMetrics
from bagmcp_gateway.upstreams.readiness import down_dependencies
from bagmcp_gateway.upstreams.tool_catalog import ToolCatalog
from bagmcp_shared.redis_errors import responds_to_ping


def readiness_router(tool_catalog: ToolCatalog, metrics: GatewayMetrics, shared_redis: redis.Redis | None) -> APIRouter:
    """``shared_redis``: the team's Redis (None when the gateway runs without one)."""
    router = APIRouter()

    @router.get("/readyz")
    def readyz() -> JSONResponse:
        """Each upstream, and Redis in team mode, up or down, and the stores a service reports down (S3 for the
        bag-store, as it said at the tool catalog's last look); the reasons go to the gateway's log, not to
        unauthenticated callers."""
        published = tool_catalog.published  # the states the routes were built from (calls follow those)
        status = {name: "up" if state.up else "down" for name, state in published.items()}
        for name, up in status.items():
            metrics.upstream_up.labels(name).set(1 if up == "up" else 0)
        redis_up = shared_redis is None or responds_to_ping(shared_redis)
        stores_down = down_dependencies({name: state.dependencies for name, state in published.items()})
        ready = all(s == "up" for s in status.values()) and not tool_catalog.conflicts and redis_up and not stores_down
        body: dict[str, object] = {
            "ready": ready,
            "upstreams": status,
            "tools": len(tool_catalog.tools),
            "conflicts": len(tool_catalog.conflicts),
        }
        if shared_redis is not None:
            body["redis"] = "up" if redis_up else "down"
        if stores_down:  # e.g. {"bag-store": ["s3"]}: the service answers, the store it needs does not
            body["stores_down"] = stores_down
        return JSONResponse(body, status_code=200 if ready else 503)

    return router


def metrics_router(metrics: GatewayMetrics) -> APIRouter:
    """Included behind the REST guard, whose scope rule asks admin for /metrics."""
    router = APIRouter()

    @router.get("/metrics")
    def exposition() -> Response:
        return Response(metrics.exposition(), media_type=metrics.content_type)

    return router
