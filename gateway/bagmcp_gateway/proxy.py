"""The REST front: /api/v1/* forwarded to the bag-store, streamed both ways, service token swapped in."""

from __future__ import annotations

import re
from collections.abc import AsyncIterator

import httpx
from fastapi import APIRouter, Request
from fastapi.responses import JSONResponse, Response, StreamingResponse

_HOP_HEADERS = {
    "host",
    "authorization",
    "connection",
    "keep-alive",
    "transfer-encoding",
    "te",
    "upgrade",
    "proxy-authorization",
    "content-length",
}


# The only bag-store routes the gateway forwards; anything else (e.g. an encoded "../mcp") is refused,
# so the service credential can never reach another endpoint.
_ROUTES = re.compile(r"^bags(/[A-Za-z0-9][A-Za-z0-9._-]{0,127}(/download)?)?$")


def forwardable(path: str) -> bool:
    """Segments start with a letter or digit and hold no '/', so no path can leave /api/v1/bags."""
    return _ROUTES.fullmatch(path) is not None


def build_proxy(base_url: str, service_token: str | None) -> APIRouter:
    router = APIRouter()
    client = httpx.AsyncClient(base_url=base_url, timeout=httpx.Timeout(30.0, read=3600.0, write=3600.0))

    @router.api_route("/api/v1/{path:path}", methods=["GET", "POST", "DELETE", "PUT", "PATCH"])
    async def forward(path: str, request: Request) -> Response:
        if not forwardable(path):
            message = f"no such route /api/v1/{path}; see /docs"
            return JSONResponse({"error": {"code": "not_found", "message": message}}, status_code=404)
        headers = {k: v for k, v in request.headers.items() if k.lower() not in _HOP_HEADERS}
        if service_token:
            headers["authorization"] = f"Bearer {service_token}"
        upstream_request = client.build_request(
            request.method,
            f"/api/v1/{path}",
            params=httpx.QueryParams(str(request.query_params)),
            headers=headers,
            content=request.stream() if request.method in ("POST", "PUT", "PATCH") else None,
        )
        try:
            upstream = await client.send(upstream_request, stream=True)
        except httpx.HTTPError as err:
            body = {
                "error": {
                    "code": "bag_store_unavailable",
                    "message": f"the bag-store service is unavailable ({type(err).__name__})",
                }
            }
            return JSONResponse(body, status_code=503)

        async def relay() -> AsyncIterator[bytes]:
            try:
                async for chunk in upstream.aiter_raw():
                    yield chunk
            finally:
                await upstream.aclose()

        out_headers = {k: v for k, v in upstream.headers.items() if k.lower() not in _HOP_HEADERS}
        return StreamingResponse(relay(), status_code=upstream.status_code, headers=out_headers)

    return router
