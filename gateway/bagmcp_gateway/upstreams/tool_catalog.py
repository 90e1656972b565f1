"""The gateway's view of its upstreams: which are up, the tools and resources each publishes and what
its instructions say, refreshed in the background so tools/list never waits for an upstream: when an
upstream announces that its tools changed (a ``subscriptions/listen`` stream kept open to each), after
a failed call, when the bus carries a change another replica noticed, and by polling as a backstop.

A down upstream's tools leave the list until it is back; every change is published as a
``tools/list_changed`` event. Tool order is deterministic: upstreams in configuration order, each
upstream's tools in its own order. A name two upstreams publish is a configuration error: at start-up
the gateway refuses to start; later (an upstream that was down at start) the newcomer's tool is left out.
Resources follow resource_routes.py.
"""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

import anyio
import httpx
import mcp.types as types
from anyio.abc import TaskStatus
from mcp import Client, MCPError
from mcp.client.subscriptions import ListenNotSupportedError
from mcp.server.subscriptions import ResourcesListChanged, ServerEvent, SubscriptionBus, ToolsListChanged
from mcp.shared.inbound import x_mcp_header_map

from bagmcp_gateway.upstreams.connections import Connections, failure_text
from bagmcp_gateway.upstreams.instructions import merged_instructions
from bagmcp_gateway.upstreams.readiness import dependencies_of, readyz_url
from bagmcp_gateway.upstreams.resource_routes import ResourceRoutes, UpstreamResources
from bagmcp_gateway.upstreams.upstream import GatewayConfigError, Upstream

log = logging.getLogger(__name__)
STARTUP_GRACE_S = 60.0  # services and the gateway start together: an upstream not answering yet is no error
NO_HEADERS: dict[str, Any] = {"type": "object"}


@dataclass
class UpstreamState:
    up: bool = False
    error: str | None = None
    tools: list[types.Tool] = field(default_factory=list)
    since: float = field(default_factory=time.time)
    instructions: str | None = None
    resources: UpstreamResources = field(default_factory=UpstreamResources)
    dependencies: dict[str, str] = field(default_factory=dict)  # what the service says of its stores (readiness)


@dataclass(frozen=True)
class ToolRoute:
    """A tool as the gateway exposes it, where it goes, and the ``Mcp-Param`` headers its schema asks for."""

    tool: types.Tool
    upstream: Upstream
    original: str
    param_headers: dict[tuple[str, ...], str] = field(default_factory=dict)


async def _resources_of(client: Client) -> UpstreamResources:
    """What the upstream publishes as resources (nothing when it offers none)."""
    capabilities = client.session.server_capabilities
    if capabilities is None or capabilities.resources is None:
        return UpstreamResources()
    try:
        resources = (await client.list_resources()).resources
        templates = (await client.list_resource_templates()).resource_templates
    except MCPError as err:
        if err.code != types.METHOD_NOT_FOUND:
            raise
        return UpstreamResources()
    return UpstreamResources(list(resources), list(templates))


class ToolCatalog:
    def __init__(
        self,
        upstreams: list[Upstream],
        connections: Connections,
        bus: SubscriptionBus,
        *,
        poll_s: float = 5.0,
        retry_s: float = 1.0,
    ) -> None:
        self.upstreams = upstreams
        self._connections = connections
        self._bus = bus
        self._poll_s = poll_s
        self._retry_s = retry_s
        self.states = {u.name: UpstreamState() for u in upstreams}
        # the states the routes were last built from: what /readyz reports. A listing round sets each state
        # as its upstream answers and builds the routes once all have; a readiness read in between said
        # "ready" while calls still answered "Unknown tool" (seen on a stack's first call after its start)
        self.published = dict(self.states)
        self.tools: list[types.Tool] = []
        self.routes: dict[str, ToolRoute] = {}
        self.resources = ResourceRoutes()
        self.known: dict[str, Upstream] = {}  # every name an upstream ever published: for "unavailable" errors
        self.conflicts: list[str] = []
        self.instructions: str | None = None
        self._wake = anyio.Event()
        self._born = time.monotonic()
        self._waited: set[str] = set()
        self._seen_up: set[str] = set()
        self._down = {u.name: anyio.Event() for u in upstreams}  # set (and replaced) each time one is found down
        self._rechecking = {u.name: anyio.Lock() for u in upstreams}
        self._rechecked: dict[str, float] = {}
        bus.subscribe(self._heard)  # a change another replica noticed: re-list here too

    @cached_property
    def _readiness_http(self) -> httpx.AsyncClient:
        """The client that reads upstreams' /readyz, made when an upstream over HTTP is first listed: one in
        memory (embedded mode) has no /readyz, and each client builds a TLS context (about 20 ms of CPU)."""
        return httpx.AsyncClient()

    async def _list(self, upstream: Upstream) -> UpstreamState:
        with anyio.fail_after(upstream.timeout_s):
            async with self._connections.client(upstream) as client:
                tools = list((await client.list_tools()).tools)
                return UpstreamState(
                    True, None, tools, instructions=client.instructions, resources=await _resources_of(client)
                )

    async def refresh(self, upstream: Upstream) -> None:
        state = self.states[upstream.name]
        try:
            listed = await self._list(upstream)
        except Exception as err:  # any failure means down; the others go on
            self._report_down(upstream, state, failure_text(err))
            self.states[upstream.name] = UpstreamState(False, failure_text(err), [], time.time())
            self._down.pop(upstream.name, anyio.Event()).set()
            self._down[upstream.name] = anyio.Event()
            return
        if readyz_url(upstream) is not None:
            listed.dependencies = await dependencies_of(upstream, self._readiness_http)
        self._seen_up.add(upstream.name)
        if not state.up or [t.name for t in listed.tools] != [t.name for t in state.tools]:
            log.info("upstream %s is up with %d tools", upstream.name, len(listed.tools))
        listed.since = state.since if state.up else time.time()
        self.states[upstream.name] = listed

    def _report_down(self, upstream: Upstream, state: UpstreamState, why: str) -> None:
        """Once per outage: a warning, except while an upstream that never answered is still starting (services
        and the gateway start together; the first seconds of "not connected" are no error)."""
        name = upstream.name
        if name not in self._seen_up and time.monotonic() - self._born < STARTUP_GRACE_S:
            if name not in self._waited:
                self._waited.add(name)
                log.info("waiting for upstream %s to start (%s)", name, why)
            return
        if state.up or state.error is None or name in self._waited:
            self._waited.discard(name)
            log.warning("upstream %s is unavailable: %s", name, why)

    async def refresh_all(self) -> bool:
        """List every upstream at once; True when the tool list changed."""
        before, resources_before = [t.name for t in self.tools], self.resources.uris()
        async with anyio.create_task_group() as group:
            for upstream in self.upstreams:
                group.start_soon(self.refresh, upstream)
        return await self._rebuilt(before, resources_before)

    async def recheck(self, upstream: Upstream) -> bool:
        """Whether ``upstream`` is up, after listing it again now if the catalog has it down: a call for one of
        its tools right after the service came back runs instead of answering "unavailable" until the next
        poll or reconnect (1-5 s after a restart). One listing per ``retry_s`` at most; callers that arrive
        meanwhile wait for it and share its verdict, so a burst of calls to a dead service costs one try."""
        name = upstream.name
        async with self._rechecking[name]:
            if not self.states[name].up and time.monotonic() - self._rechecked.get(name, 0.0) >= self._retry_s:
                self._rechecked[name] = time.monotonic()
                before, resources_before = [t.name for t in self.tools], self.resources.uris()
                await self.refresh(upstream)
                await self._rebuilt(before, resources_before)
        return self.states[name].up

    async def _rebuilt(self, before: list[str], resources_before: list[str]) -> bool:
        """Routes rebuilt from the states; clients told when tools or resources changed (True for tools)."""
        self._rebuild()
        changed = before != [t.name for t in self.tools]
        if changed:
            await self._bus.publish(ToolsListChanged())
        if resources_before != self.resources.uris():
            await self._bus.publish(ResourcesListChanged())
        return changed

    def _rebuild(self) -> None:
        tools: list[types.Tool] = []
        routes: dict[str, ToolRoute] = {}
        conflicts: list[str] = []
        for upstream in self.upstreams:
            for tool in self.states[upstream.name].tools:
                name = upstream.exposed(tool.name)
                if name in routes:
                    conflicts.append(
                        f"tool {name!r} is published by {routes[name].upstream.name} and {upstream.name}; "
                        f"give one of them a prefix in BAGMCP_UPSTREAMS (name=url@prefix)"
                    )
                    continue
                exposed = upstream.exposed_tool(tool)
                routes[name] = ToolRoute(exposed, upstream, tool.name, x_mcp_header_map(tool.input_schema))
                self.known[name] = upstream
                tools.append(exposed)
        self.tools, self.routes, self.conflicts = tools, routes, conflicts
        self.published = dict(self.states)
        up = [(u, self.states[u.name].resources) for u in self.upstreams if self.states[u.name].up]
        self.resources = ResourceRoutes.build(up)
        self.instructions = merged_instructions([s.instructions for s in self.states.values() if s.up])
        for message in conflicts:
            log.error("gateway configuration error: %s", message)

    def check_startup(self) -> None:
        if self.conflicts:
            raise GatewayConfigError("; ".join(self.conflicts))

    def header_schema(self, name: str) -> dict[str, Any] | None:
        """What the SDK checks a call's ``Mcp-Param`` headers against: the tool's input schema when it
        declares such headers, else an empty object schema (the same verdict, without walking the schema)."""
        route = self.routes.get(name)
        if route is None:
            return None
        return route.tool.input_schema if route.param_headers else NO_HEADERS

    def tools_of(self, upstream: Upstream) -> list[types.Tool]:
        """The tools the gateway exposes for ``upstream`` now."""
        return [route.tool for route in self.routes.values() if route.upstream.name == upstream.name]

    async def went_down(self, upstream: Upstream) -> str:
        """Returns, with the reason, once a listing of ``upstream`` fails after this was called (a call in
        flight to it then ends at once instead of at its call limit, 600 s by default)."""
        await self._down[upstream.name].wait()
        return self.states[upstream.name].error or "it stopped answering"

    def failed(self, upstream: Upstream) -> None:
        """A call to ``upstream`` failed in transport: re-list soon instead of at the next poll."""
        self._wake.set()

    def _heard(self, event: ServerEvent) -> None:
        if isinstance(event, ToolsListChanged):
            self._wake.set()

    async def run(self, *, task_status: TaskStatus[None] = anyio.TASK_STATUS_IGNORED) -> None:
        """Keep the catalog fresh until cancelled."""
        async with anyio.create_task_group() as group:
            for upstream in self.upstreams:
                group.start_soon(self._follow, upstream)
            task_status.started()
            while True:
                with anyio.move_on_after(self._poll_s):
                    await self._wake.wait()
                self._wake = anyio.Event()
                await self.refresh_all()

    async def _follow(self, upstream: Upstream) -> None:
        """Re-list as soon as ``upstream`` says its tools changed; when its stream is lost (a stopped or
        restarting service drops it at once), so the catalog has it down now rather than at the next poll;
        and once it is back (a change may have gone unheard meanwhile). Servers that cannot stream changes are
        polled only. Polling stays the backstop for a service that stops answering without closing its
        connections (a frozen host): its listing then fails after the upstream's timeout."""
        lost = False
        while True:
            try:
                async with (
                    upstream.client(listening=True) as client,
                    client.listen(tools_list_changed=True) as changes,
                ):
                    if lost:
                        self._wake.set()
                    lost = False
                    async for _change in changes:
                        self._wake.set()
            except Exception as err:  # down or dropped: try again shortly
                if _cannot_listen(err):
                    log.info("upstream %s cannot announce tool changes: polled only", upstream.name)
                    return
                log.debug("change stream of upstream %s lost: %s", upstream.name, err)
            if not lost:
                self._wake.set()  # once per loss, not on every failed reconnect while it stays down
            lost = True
            await anyio.sleep(self._retry_s)


def _cannot_listen(err: Exception) -> bool:
    """A server of the 2025 protocol, or one without ``subscriptions/listen`` (perhaps inside a group)."""
    if isinstance(err, ExceptionGroup):
        return any(_cannot_listen(inner) for inner in err.exceptions)
    return isinstance(err, ListenNotSupportedError) or (
        isinstance(err, MCPError) and err.code == types.METHOD_NOT_FOUND
    )
