"""The REST front: /api/v1/<segment>/... forwarded to the service configured for that segment,
streamed both ways, the service credential swapped in for the caller's token.

A segment in ``caller_segments`` (the Lab) also gets the caller's own bearer token in ``x-bagmcp-caller``: that
service acts for the caller on this gateway's /mcp, where the caller's token and profile are checked again."""

from __future__ import annotations

import re
from collections.abc import AsyncIterator, Collection, Mapping

import httpx
from fastapi import APIRouter, Request
from fastapi.responses import Response, StreamingResponse

from bagmcp_kit.http_errors import error_response
from bagmcp_kit.identity import TOOLS_HEADER

CALLER_HEADER = "x-bagmcp-caller"
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
    "origin",  # the gateway checked it; the service behind answers to the gateway, not to the browser
    CALLER_HEADER,  # set only by the gateway, never passed on from a client
    TOOLS_HEADER,  # only the gateway names the tools a caller may call
}
# The only paths the gateway forwards: a configured segment, then at most two plain segments that start
# with a letter or digit and hold no '/'. Anything else (e.g. an encoded "../mcp") is refused, so the
# service credential can never reach another endpoint.
_PATH = re.compile(r"^([a-z]+)(/[A-Za-z0-9][A-Za-z0-9._-]{0,127}(/[a-z]+)?)?$")


def route_of(path: str, routes: Mapping[str, str]) -> str | None:
    """The base URL that serves ``/api/v1/<path>``, or None when the path may not be forwarded."""
    match = _PATH.fullmatch(path)
    return routes.get(match.group(1)) if match else None


def forwarded_headers(
    headers: Mapping[str, str], path: str, *, service_token: str | None, caller_segments: Collection[str]
) -> dict[str, str]:
    """What the service behind ``/api/v1/<path>`` is sent: the client's headers less the hop ones (its token and
    any ``x-bagmcp-caller`` it made up), the service credential, and for ``caller_segments`` the caller's token."""
    out = {k: v for k, v in headers.items() if k.lower() not in _HOP_HEADERS}
    if service_token:
        out["authorization"] = f"Bearer {service_token}"
    caller = next((v for k, v in headers.items() if k.lower() == "authorization"), None)
    if path.split("/")[0] in caller_segments and caller:
        out[CALLER_HEADER] = caller
    return out


def build_proxy(
    routes: Mapping[str, str], service_token: str | None, *, caller_segments: Collection[str] = ()
) -> APIRouter:
    router = APIRouter()
    client = httpx.AsyncClient(timeout=httpx.Timeout(30.0, read=3600.0, write=3600.0))

    @router.api_route("/api/v1/{path:path}", methods=["GET", "POST", "DELETE", "PUT", "PATCH"])
    async def forward(path: str, request: Request) -> Response:
        base = route_of(path, routes)
        if base is None:
            return error_response(404, "not_found", f"no such route /api/v1/{path}; see /docs")
        headers = forwarded_headers(request.headers, path, service_token=service_token, caller_segments=caller_segments)
        if (tools := getattr(request.state, "bagmcp_tools", None)) is not None:
            headers[TOOLS_HEADER] = ",".join(tools)
        upstream_request = client.build_request(
            request.method,
            f"{base}/api/v1/{path}",
            params=httpx.QueryParams(str(request.query_params)),
            headers=headers,
            content=request.stream() if request.method in ("POST", "PUT", "PATCH") else None,
        )
        try:
            upstream = await client.send(upstream_request, stream=True)
        except httpx.HTTPError as err:
            message = f"the service behind /api/v1/{path.split('/')[0]} is unavailable ({type(err).__name__})"
            return error_response(503, "service_unavailable", message)

        async def relay() -> AsyncIterator[bytes]:
            try:
                async for chunk in upstream.aiter_raw():
                    yield chunk
            finally:
                await upstream.aclose()

        out_headers = {k: v for k, v in upstream.headers.items() if k.lower() not in _HOP_HEADERS}
        return StreamingResponse(relay(), status_code=upstream.status_code, headers=out_headers)

    return router
