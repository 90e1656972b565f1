"""A service's MCP server, guarded by the service credential when it serves over HTTP."""

from __future__ import annotations

from mcp.server.auth.settings import AuthSettings
from mcp.server.mcpserver import MCPServer
from pydantic import AnyHttpUrl

from bagmcp_kit.arguments import CONVENTIONS
from bagmcp_kit.auth import SERVICE_SCOPE, ServiceTokenVerifier


def new_server(
    name: str, *, purpose: str, service_token: str | None = None, public_url: str = "http://127.0.0.1:8000"
) -> MCPServer:
    """An MCP server whose instructions state what it is for and the shared conventions once.

    With ``service_token`` every call must carry it (the gateway's credential); without one the
    server is for in-process use (embedded mode, tests)."""
    instructions = f"{purpose} {CONVENTIONS}"
    if service_token is None:
        return MCPServer(name, instructions=instructions)
    auth = AuthSettings(
        issuer_url=AnyHttpUrl(public_url),
        resource_server_url=AnyHttpUrl(f"{public_url}/mcp"),
        required_scopes=[SERVICE_SCOPE],
        validate_token_resource=False,
    )
    return MCPServer(name, instructions=instructions, token_verifier=ServiceTokenVerifier(service_token), auth=auth)
