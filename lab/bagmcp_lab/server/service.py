"""What the Lab's routes share: its settings, the runs going, where the gateway's MCP endpoint is, and how a
request names its caller (the token the agent loops call MCP with, so the caller's profile applies)."""

from __future__ import annotations

import hashlib
from collections.abc import Callable
from dataclasses import dataclass, field

import httpx2
from fastapi import Request

from bagmcp_lab.server.runs import RunRegistry
from bagmcp_lab.settings import LabSettings

# The header the gateway puts a caller's own bearer token in when it forwards a Lab request to the Lab
# service (whose Authorization header holds the service credential).
CALLER_HEADER = "x-bagmcp-caller"
LOCAL_OWNER = "local"


@dataclass(frozen=True)
class Caller:
    token: str | None
    owner: str  # runs belong to this (a hash of the token; never the token itself)


@dataclass
class McpTarget:
    """The gateway's MCP endpoint; ``transport`` reaches it in process (embedded) instead of over a socket."""

    url: str
    transport: Callable[[], httpx2.AsyncBaseTransport | None] = lambda: None


@dataclass
class LabService:
    settings: LabSettings
    target: McpTarget
    caller_header: str = "authorization"
    registry: RunRegistry = field(init=False)

    def __post_init__(self) -> None:
        self.registry = RunRegistry(self.settings.runs_per_caller, self.settings.kept_runs)

    def caller(self, request: Request) -> Caller:
        scheme, _, token = request.headers.get(self.caller_header, "").partition(" ")
        if scheme.lower() != "bearer" or not token.strip():
            return Caller(None, LOCAL_OWNER)
        owner = hashlib.sha256(token.strip().encode()).hexdigest()[:16]
        return Caller(token.strip(), owner)
