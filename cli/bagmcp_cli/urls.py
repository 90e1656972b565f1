"""Server URLs as people paste them: the base (``http://host:8080``) or the MCP endpoint (``.../mcp``), with or
without a trailing slash. Every command takes either form and turns it into the one it needs, so a pasted URL
never ends in a bare 404."""

from __future__ import annotations

MCP_PATH = "/mcp"


def base_url(url: str) -> str:
    """``http://h:8080/mcp/`` -> ``http://h:8080`` (where the REST API lives, under /api/v1)."""
    trimmed = url.strip().rstrip("/")
    return trimmed[: -len(MCP_PATH)] if trimmed.endswith(MCP_PATH) else trimmed


def mcp_url(url: str) -> str:
    """``http://h:8080`` -> ``http://h:8080/mcp`` (the endpoint MCP clients connect to)."""
    return base_url(url) + MCP_PATH
