"""A service's MCP server, guarded by the service credential when it serves over HTTP."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from mcp.server.auth.settings import AuthSettings
from mcp.server.mcpserver import MCPServer
from pydantic import AnyHttpUrl

from bagmcp_kit.arguments import CONVENTIONS, ToolSpec, register
from bagmcp_kit.auth import SERVICE_SCOPE, ServiceTokenVerifier
from bagmcp_kit.fetch_meta import fetched_bytes_meta
from bagmcp_kit.ingest_wait import IngestWait, wait_for_ingest
from bagmcp_kit.web.viewers import add_viewer, ui_meta
from bagmcp_shared.settings import ServiceSettings


@dataclass(frozen=True)
class McpGuard:
    """What a service's MCP server checks over HTTP: the service credential every call carries (the
    gateway's), and the URL the service is reached at (named in its auth metadata)."""

    service_token: str
    public_url: str

    @classmethod
    def of(cls, settings: ServiceSettings) -> McpGuard:
        return cls(settings.team.service_token, settings.public_url)


def new_server(
    name: str,
    *,
    purpose: str,
    tools: Sequence[ToolSpec],
    guard: McpGuard | None = None,
    ingest: IngestWait | None = None,
) -> MCPServer:
    """An MCP server with ``tools`` (declared, kit/declared.py; in order), whose instructions state
    what it is for and the shared conventions once. Tools marked with a view point at the service's MCP
    Apps viewer, ``ui://<name without "bagmcp-">/viewer.html``, served here as a resource.

    Without a ``guard`` the server is for in-process use (embedded mode, tests). With ``ingest``, a call about a
    bag still being ingested waits for it (see ingest_wait.py)."""
    instructions = f"{purpose} {CONVENTIONS}"
    if guard is None:
        server = MCPServer(name, instructions=instructions)
    else:
        auth = AuthSettings(
            issuer_url=AnyHttpUrl(guard.public_url),
            resource_server_url=AnyHttpUrl(f"{guard.public_url}/mcp"),
            required_scopes=[SERVICE_SCOPE],
            validate_token_resource=False,
        )
        server = MCPServer(
            name, instructions=instructions, token_verifier=ServiceTokenVerifier(guard.service_token), auth=auth
        )
    viewer = ui_meta(add_viewer(server, name.removeprefix("bagmcp-"))) if any(s.view for s in tools) else None
    register(server, tools, viewer_meta=viewer)
    server.middleware.append(fetched_bytes_meta)
    if ingest is not None:
        server.middleware.append(wait_for_ingest(ingest.catalog, budget_s=ingest.budget_s))
    return server
