"""Long-lived MCP clients to the upstreams, so a tool call costs one request, not a new session.

Each upstream's client is owned by a background task (anyio needs a client to be opened and
closed in one task); calls from request handlers use it. A call that fails marks the client
stale, and the task reconnects. While no client is connected, calls open a one-off client.
"""

from __future__ import annotations

import logging
from collections.abc import AsyncIterator
from contextlib import asynccontextmanager

import anyio
from anyio.abc import TaskStatus
from mcp import Client

from bagmcp_gateway.upstreams import Upstream

log = logging.getLogger(__name__)


async def _passed_on_unchecked(name: str, result: object) -> None:
    """The gateway relays results as they are; the caller's own client checks them against the schema."""


def trusting(client: Client) -> Client:
    """``client`` without the SDK's check of every result against the tool's output schema (jsonschema on
    each call, about a sixth of the gateway's time per cheap call); the end client validates anyway."""
    client.session.validate_tool_result = _passed_on_unchecked  # type: ignore[method-assign]
    return client


class Connections:
    def __init__(self, upstreams: list[Upstream], *, retry_s: float = 1.0) -> None:
        self._upstreams = upstreams
        self._retry_s = retry_s
        self._clients: dict[str, Client] = {}
        self._stale: dict[str, anyio.Event] = {}

    async def run(self, *, task_status: TaskStatus[None] = anyio.TASK_STATUS_IGNORED) -> None:
        """Keep every upstream connected until cancelled."""
        async with anyio.create_task_group() as group:
            for upstream in self._upstreams:
                group.start_soon(self._keep, upstream)
            task_status.started()

    async def _keep(self, upstream: Upstream) -> None:
        while True:
            stale = anyio.Event()
            self._stale[upstream.name] = stale
            try:
                async with upstream.client() as client:
                    self._clients[upstream.name] = trusting(client)
                    await stale.wait()
            except Exception as err:  # down or dropped: try again shortly
                log.info("upstream %s not connected: %s", upstream.name, err)
            finally:
                self._clients.pop(upstream.name, None)
            await anyio.sleep(self._retry_s)

    def connected(self, name: str) -> bool:
        """Whether the upstream called ``name`` has a live long-lived client right now."""
        return name in self._clients

    @asynccontextmanager
    async def client(self, upstream: Upstream) -> AsyncIterator[Client]:
        """The upstream's long-lived client, or a one-off one while it is not connected."""
        held = self._clients.get(upstream.name)
        if held is None:
            async with upstream.client() as fresh:
                yield trusting(fresh)
            return
        try:
            yield held
        except Exception:
            if (stale := self._stale.get(upstream.name)) is not None:
                stale.set()
            raise
