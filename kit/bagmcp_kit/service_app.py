"""The FastAPI skeleton every bagmcp app shares (errors in one shape, guarded REST routes, /healthz),
``create_service_app`` for a service (its MCP server at /mcp, REST under /api/v1) and ``serve``."""

from __future__ import annotations

import contextlib
import errno
import math
import socket
from collections.abc import AsyncIterator, Awaitable, Callable, Mapping, Sequence
from contextlib import AbstractAsyncContextManager

import uvicorn
from fastapi import APIRouter, Depends, FastAPI, Request
from fastapi.responses import JSONResponse, PlainTextResponse
from mcp.server.mcpserver import MCPServer
from mcp.server.transport_security import TransportSecuritySettings

from bagmcp_kit.access_log import redact_access_log
from bagmcp_kit.auth import rest_guard
from bagmcp_kit.error_shape import UniformErrors
from bagmcp_kit.host_check import HostAllowList
from bagmcp_kit.http_errors import StatusTable, install_error_handlers
from bagmcp_shared.errors import SettingsError
from bagmcp_shared.settings import HttpSettings

RestGuard = Callable[[Request], Awaitable[None]]  # a REST route dependency: returns, or raises the refusal
Metrics = Callable[[], Mapping[str, Mapping[str, int] | None]]  # counters by process label (None: unavailable)


def new_app(
    *,
    title: str,
    lifespan: Callable[[FastAPI], AbstractAsyncContextManager[None]],
    routers: Sequence[APIRouter],
    guard: RestGuard,
    allowed_hosts: Sequence[str],
    statuses: StatusTable = (),
) -> FastAPI:
    """An app with the project's error shape, ``routers`` behind ``guard``, /healthz, and every route
    answering only to ``allowed_hosts`` (DNS-rebinding protection)."""
    app = FastAPI(title=title, lifespan=lifespan)
    app.add_middleware(HostAllowList, allowed=allowed_hosts)
    install_error_handlers(app, statuses)
    for router in routers:
        app.include_router(router, dependencies=[Depends(guard)])

    @app.get("/healthz")
    def healthz() -> dict[str, bool]:
        return {"ok": True}

    return app


# Host and Origin are checked for every route, /mcp included, by the app's HostAllowList (one rule, one
# error shape); the SDK's own check would refuse an Origin that rule allows, so it is left off.
HOST_CHECK_IN_MIDDLEWARE = TransportSecuritySettings(enable_dns_rebinding_protection=False)


def create_service_app(
    *,
    title: str,
    server: MCPServer,
    routers: Sequence[APIRouter] = (),
    service_token: str | None,
    allowed_hosts: Sequence[str],
    statuses: StatusTable = (),
    on_shutdown: Callable[[], None] | None = None,
    checks: Mapping[str, Callable[[], bool]] | None = None,
    metrics: Metrics | None = None,
) -> FastAPI:
    """The service as an ASGI app. With ``service_token`` both MCP and REST require it, and /metrics (the
    counters ``metrics`` gives by process, in Prometheus' text format) too. ``checks`` name the stores the service needs
    (``{"s3": ...}``), each True while it answers: ``/readyz`` says each up or down (503 when one is down), and
    the gateway's /readyz repeats it."""
    security = HOST_CHECK_IN_MIDDLEWARE
    mcp_app = server.streamable_http_app(streamable_http_path="/mcp", transport_security=security)

    @contextlib.asynccontextmanager
    async def lifespan(_app: FastAPI) -> AsyncIterator[None]:
        async with server.session_manager.run():
            yield
        if on_shutdown is not None:
            on_shutdown()

    app = new_app(
        title=title,
        lifespan=lifespan,
        routers=routers,
        guard=rest_guard(service_token),
        allowed_hosts=allowed_hosts,
        statuses=statuses,
    )
    install_readiness(app, checks or {})
    if metrics is not None:
        add_metrics_route(app, metrics, rest_guard(service_token))
    app.mount("/", UniformErrors(mcp_app))
    return app


def install_readiness(app: FastAPI, checks: Mapping[str, Callable[[], bool]]) -> None:
    """``GET /readyz``: ``{"ready": bool, name: "up" | "down" ...}``, unauthenticated (names, no reasons)."""

    @app.get("/readyz")
    def readyz() -> JSONResponse:
        states = {name: "up" if check() else "down" for name, check in checks.items()}
        ready = all(state == "up" for state in states.values())
        return JSONResponse({"ready": ready, **states}, status_code=200 if ready else 503)


def add_metrics_route(app: FastAPI, metrics: Metrics, guard: RestGuard) -> None:
    """GET /metrics behind ``guard``, in Prometheus' text format: per counter ``# TYPE name counter``, then one
    ``name{process="..."} value`` line per process that has it (``service``: this one; ``workers``: the sum
    of the service's workers); a process whose counters are unavailable now is a comment saying so."""

    @app.get("/metrics", dependencies=[Depends(guard)])
    def exposition() -> PlainTextResponse:
        return PlainTextResponse(exposition_text(metrics()), media_type="text/plain; version=0.0.4")


def exposition_text(by_process: Mapping[str, Mapping[str, int] | None]) -> str:
    """The counters of each process as Prometheus text, one family (TYPE line) per counter name."""
    names = list(dict.fromkeys(name for counters in by_process.values() for name in counters or {}))
    lines = [f"# {process} counters unavailable now" for process, counters in by_process.items() if counters is None]
    for name in names:
        lines.append(f"# TYPE {name} counter")
        for process, counters in by_process.items():
            if counters is not None and name in counters:
                lines.append(f'{name}{{process="{process}"}} {counters[name]}')
    return "\n".join(lines) + "\n"


def serve(
    app: FastAPI,
    http: HttpSettings,
    *,
    log_level: str = "info",
    announce: Callable[[], None] | None = None,
    sock: socket.socket | None = None,
) -> None:
    """Run ``app`` where ``http`` says (or on ``sock``, bound already), until interrupted (access logs never show a
    secret sent in a query).

    The socket is bound first, so a port in use is one clear error (a SettingsError) before anything says it
    serves, and ``announce`` runs only once the socket is listening. On SIGTERM or Ctrl-C, requests still open
    get ``http.stop_grace_s`` to end, then are closed: uvicorn would otherwise wait for them without limit, and
    a service always has some (the gateway's links, a call waiting for a job), so every stop ended in SIGKILL."""
    redact_access_log()
    sock = sock if sock is not None else bound_socket(http.host, http.port)
    if announce is not None:
        announce()
    config = uvicorn.Config(app, log_level=log_level, timeout_graceful_shutdown=math.ceil(http.stop_grace_s))
    uvicorn.Server(config).run(sockets=[sock])


def bound_socket(host: str, port: int) -> socket.socket:
    """A listening TCP socket on ``host:port`` (SO_REUSEADDR, as uvicorn sets it).

    Made with ``IPPROTO_TCP`` named, not 0: asyncio turns Nagle's algorithm off (TCP_NODELAY) only on sockets
    whose ``proto`` says TCP, and accepted connections inherit it. Without it every answer written in two
    parts (headers, then body) waited for the client's delayed ACK: about 45 ms per request (bench/notes.md)."""
    family = socket.AF_INET6 if ":" in host else socket.AF_INET
    sock = socket.socket(family, socket.SOCK_STREAM, socket.IPPROTO_TCP)
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    try:
        sock.bind((host, port))
    except OSError as err:
        sock.close()
        if err.errno == errno.EADDRINUSE:
            raise SettingsError(
                f"port {port} on {host} is in use (another bagmcp?); stop that server or pick another port"
            ) from err
        raise SettingsError(f"cannot listen on {host}:{port}: {err.strerror or err}") from err
    sock.listen(2048)
    sock.set_inheritable(True)
    return sock
