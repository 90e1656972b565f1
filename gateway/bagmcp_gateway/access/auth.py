"""REST authentication at the gateway: a valid bearer token, and the scope the route needs
(upload to upload, delete to delete, admin for tokens and metrics, read for the rest); the tools the
token may call, kept on the request for routes that answer across bags (the proxy forwards them), and
checked against the tools that give the route's data (rest_policy.py)."""

from __future__ import annotations

from collections.abc import Awaitable, Callable

from fastapi import Request
from mcp.server.auth.provider import AccessToken

from bagmcp_gateway.access.rest_policy import rest_refusal
from bagmcp_gateway.access.tokens.verifier import GatewayVerifier
from bagmcp_kit.http_errors import HttpError


def scope_for(method: str, path: str) -> str:
    if path.startswith(("/api/v1/tokens", "/metrics")):
        return "admin"
    if path.startswith("/api/v1/bags") and method == "POST":
        return "upload"
    if method == "DELETE":
        return "delete"
    return "read"


ToolsFor = Callable[[AccessToken | None], Awaitable[list[str] | None]]


def rest_auth(
    verifier: GatewayVerifier | None, tools_for: ToolsFor | None = None
) -> Callable[[Request], Awaitable[None]]:
    """A FastAPI dependency requiring a valid bearer token with the route's scope (none without a verifier);
    ``tools_for`` names the tools the caller may call (``request.state.bagmcp_tools``, None: every one)."""

    async def allowed_tools(request: Request, access: AccessToken | None) -> None:
        if tools_for is None:
            return
        tools = await tools_for(access)
        request.state.bagmcp_tools = tools
        if (refusal := rest_refusal(request.method, request.url.path, tools)) is not None:
            raise HttpError(403, "forbidden", refusal)

    async def check(request: Request) -> None:
        if verifier is None:
            await allowed_tools(request, None)
            return
        scheme, _, token = request.headers.get("authorization", "").partition(" ")
        access = await verifier.verify_token(token.strip()) if scheme.lower() == "bearer" and token else None
        if access is None:
            raise HttpError(401, "unauthorized", "a valid bearer token is required", bearer=True)
        needed = scope_for(request.method, request.url.path)
        if needed not in access.scopes:
            raise HttpError(403, "forbidden", f"this token lacks the {needed!r} scope this route needs")
        await allowed_tools(request, access)

    return check
