"""Upstream MCP servers the gateway aggregates: over HTTP with the service token, or in-process."""

from __future__ import annotations

import re
from collections.abc import AsyncIterator
from contextlib import asynccontextmanager
from dataclasses import dataclass

import httpx2
import mcp.types as types
from mcp import Client
from mcp.client.streamable_http import streamable_http_client
from mcp.server.mcpserver import MCPServer

from bagmcp_shared.errors import BagmcpError

_UPSTREAM_NAME = re.compile(r"^[a-z][a-z0-9-]*$")
UI_SCHEME = "ui://"
# How long the gateway waits to connect to an upstream and list its tools before it counts as down
# (BAGMCP_UPSTREAM_TIMEOUT_S): a frozen service, one that keeps its connections open but never answers, leaves
# tools/list after this plus at most a poll.
DEFAULT_UPSTREAM_TIMEOUT_S = 10.0


class GatewayConfigError(BagmcpError):
    """The gateway's upstream configuration is invalid (bad name, tool name collision)."""


@dataclass(frozen=True)
class Upstream:
    """One upstream MCP server. Exactly one of ``url`` (team mode) or ``server`` (embedded) is set.

    ``prefix`` is prepended to its tool names (``prefix__tool``) and resource URIs (``prefix+uri``); it is
    only needed when two upstreams publish a tool of the same name.
    """

    name: str
    url: str | None = None
    server: MCPServer | None = None
    service_token: str | None = None
    prefix: str | None = None
    timeout_s: float = DEFAULT_UPSTREAM_TIMEOUT_S
    call_timeout_s: float = 600.0

    def __post_init__(self) -> None:
        if not _UPSTREAM_NAME.match(self.name):
            raise GatewayConfigError(f"upstream name {self.name!r} must match [a-z][a-z0-9-]*")
        if (self.url is None) == (self.server is None):
            raise GatewayConfigError(f"upstream {self.name}: give either a url or an in-process server")

    def exposed(self, tool: str) -> str:
        return f"{self.prefix}__{tool}" if self.prefix else tool

    def exposed_uri(self, uri: str) -> str:
        """``prefix+uri``; an MCP Apps viewer keeps its scheme (hosts render only ``ui://``): ``ui://prefix.rest``."""
        if not self.prefix:
            return uri
        if uri.startswith(UI_SCHEME):
            return f"{UI_SCHEME}{self.prefix}.{uri[len(UI_SCHEME) :]}"
        return f"{self.prefix}+{uri}"

    def original_uri(self, exposed: str) -> str | None:
        """The URI this upstream knows for ``exposed``, or None when ``exposed`` is not one of its own."""
        if not self.prefix:
            return exposed
        for head, restored in ((f"{UI_SCHEME}{self.prefix}.", UI_SCHEME), (f"{self.prefix}+", "")):
            if exposed.startswith(head):
                return restored + exposed[len(head) :]
        return None

    def exposed_tool(self, tool: types.Tool) -> types.Tool:
        """``tool`` under its exposed name, its Apps viewer (``_meta.ui.resourceUri``) under its exposed URI."""
        update: dict[str, object] = {"name": self.exposed(tool.name)}
        ui = tool.meta.get("ui") if tool.meta else None
        if self.prefix and isinstance(ui, dict) and isinstance(uri := ui.get("resourceUri"), str):
            update["meta"] = {**(tool.meta or {}), "ui": {**ui, "resourceUri": self.exposed_uri(uri)}}
        return tool.model_copy(update=update)

    @asynccontextmanager
    async def client(self, *, listening: bool = False) -> AsyncIterator[Client]:
        """A connected MCP client for this upstream (no response cache: the gateway re-lists). A
        ``listening`` client holds a change-event stream open, so reads on it never time out."""
        if self.server is not None:
            async with Client(self.server, cache=None) as client:
                yield client
            return
        assert self.url is not None
        headers = {"Authorization": f"Bearer {self.service_token}"} if self.service_token else {}
        read_s = None if listening else self.call_timeout_s
        http = httpx2.AsyncClient(headers=headers, timeout=httpx2.Timeout(self.timeout_s, read=read_s))
        async with http, Client(streamable_http_client(self.url, http_client=http), cache=None) as client:
            yield client
