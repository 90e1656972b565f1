"""Long-lived links to the upstreams, so a request costs one exchange, not a new session.

Each upstream's MCP client is owned by a background task (anyio needs a client to be opened and closed
in one task); request handlers use it. An upstream on plain ``http://`` that negotiated the stateless
2026-07-28 protocol also gets a ``JsonRpcRelay``: requests whose answers the gateway passes on as they are
go through it as JSON, without the SDK's models. A request that fails marks the link stale, and the task
reconnects. While no client is connected, requests open a one-off client.
"""

from __future__ import annotations

import logging
from collections.abc import AsyncIterator
from contextlib import asynccontextmanager
from dataclasses import dataclass

import anyio
from anyio.abc import TaskStatus
from mcp import Client, MCPError
from mcp_types.version import MODERN_PROTOCOL_VERSIONS

from bagmcp_gateway.upstreams.relay import JsonRpcRelay
from bagmcp_gateway.upstreams.upstream import Upstream

log = logging.getLogger(__name__)


async def _passed_on_unchecked(name: str, result: object) -> None:
    """The gateway relays results as they are; the caller's own client checks them against the schema."""


def trusting(client: Client) -> Client:
    """``client`` without the SDK's check of every result against the tool's output schema (jsonschema on
    each call, about a sixth of the gateway's time per cheap call); the end client validates anyway."""
    client.session.validate_tool_result = _passed_on_unchecked  # type: ignore[method-assign]
    return client


@dataclass(frozen=True)
class Link:
    """How to reach one upstream now: its MCP client, and its relay when it has one."""

    client: Client
    relay: JsonRpcRelay | None = None


def _relay_for(upstream: Upstream, client: Client) -> JsonRpcRelay | None:
    """A relay for an ``http://`` upstream on the 2026-07-28 protocol (the team's own services); others
    (older servers, ``https://`` ones behind TLS or proxies) are reached through the SDK client."""
    url = upstream.url
    if url is None or not url.startswith("http://") or client.session.protocol_version not in MODERN_PROTOCOL_VERSIONS:
        return None
    headers = {"Authorization": f"Bearer {upstream.service_token}"} if upstream.service_token else {}
    return JsonRpcRelay(upstream.name, url, headers=headers, timeout_s=upstream.timeout_s)


def failure_text(err: BaseException) -> str:
    """What went wrong, in one line: the innermost error of nested task groups ("ConnectError: All connection
    attempts failed", not "unhandled errors in a TaskGroup")."""
    while isinstance(err, BaseExceptionGroup) and len(err.exceptions) == 1:
        err = err.exceptions[0]
    return f"{type(err).__name__}: {err}" if str(err) else type(err).__name__


def sole_error(group: ExceptionGroup[Exception]) -> Exception:
    """The one exception ``group`` holds (so callers see an error answer as such), or the group itself."""
    inner = group.exceptions[0] if len(group.exceptions) == 1 else group
    return sole_error(inner) if isinstance(inner, ExceptionGroup) and inner is not group else inner


class Connections:
    def __init__(self, upstreams: list[Upstream], *, retry_s: float = 1.0) -> None:
        self._upstreams = upstreams
        self._retry_s = retry_s
        self._links: dict[str, Link] = {}
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
            relay = None
            try:
                async with upstream.client() as client:
                    relay = _relay_for(upstream, client)
                    self._links[upstream.name] = Link(trusting(client), relay)
                    await stale.wait()
            except Exception as err:  # down, dropped or not started yet: try again shortly (the catalog reports it)
                log.debug("upstream %s not connected: %s", upstream.name, failure_text(err))
            finally:
                self._links.pop(upstream.name, None)
                if relay is not None:
                    with anyio.CancelScope(shield=True):
                        await relay.close()
            await anyio.sleep(self._retry_s)

    def connected(self, name: str) -> bool:
        """Whether the upstream called ``name`` has a live long-lived client right now."""
        return name in self._links

    @asynccontextmanager
    async def link(self, upstream: Upstream) -> AsyncIterator[Link]:
        """The upstream's long-lived link, or a one-off client while it is not connected; a failure inside
        (other than an error answer) marks the long-lived link stale."""
        held = self._links.get(upstream.name)
        if held is None:
            try:
                async with upstream.client() as fresh:
                    yield Link(trusting(fresh))
            except ExceptionGroup as group:  # the client's task group wraps what was raised inside
                raise sole_error(group) from None
            return
        try:
            yield held
        except MCPError:  # the upstream answered (with an error): the link works
            raise
        except Exception:
            if (stale := self._stale.get(upstream.name)) is not None:
                stale.set()
            raise

    @asynccontextmanager
    async def client(self, upstream: Upstream) -> AsyncIterator[Client]:
        """The upstream's MCP client (long-lived, or one-off while it is not connected)."""
        async with self.link(upstream) as link:
            yield link.client
