"""The aggregated MCP server served over streamable HTTP at /mcp: stateless, answers as event streams, the Host
check left to the app's middleware, and, when tokens are checked, the SDK's bearer auth with ``read`` required
(the tool policy then decides per tool)."""

from __future__ import annotations

from typing import Any

from mcp.server import Server
from mcp.server.auth.settings import AuthSettings
from pydantic import AnyHttpUrl
from starlette.applications import Starlette

from bagmcp_gateway.access.tokens.verifier import GatewayVerifier
from bagmcp_kit.service_app import HOST_CHECK_IN_MIDDLEWARE


def mcp_endpoint(server: Server[Any], verifier: GatewayVerifier | None, *, public_url: str) -> Starlette:
    auth = None
    if verifier is not None:
        auth = AuthSettings(
            issuer_url=AnyHttpUrl(public_url),
            resource_server_url=AnyHttpUrl(f"{public_url}/mcp"),
            required_scopes=["read"],
            validate_token_resource=False,
        )
    return server.streamable_http_app(
        streamable_http_path="/mcp",
        stateless_http=True,
        json_response=False,
        transport_security=HOST_CHECK_IN_MIDDLEWARE,
        auth=auth,
        token_verifier=verifier,
    )
