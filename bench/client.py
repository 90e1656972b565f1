"""MCP calls as a client makes them (the official client over streamable HTTP), timed."""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Any

from mcp import Client

from bench.stats import Timing
from tests.fixtures.mcp_client import text_of


class CallFailedError(RuntimeError):
    """A call the benchmark needs to succeed answered an error (or only a job: its budget ran out)."""


@dataclass(frozen=True)
class Endpoint:
    """An MCP URL and the bearer token it takes (None: none needed)."""

    url: str
    token: str | None


async def call(client: Client, tool: str, arguments: dict[str, Any]) -> dict[str, Any]:
    """Call ``tool``; its structured content, or CallFailedError with the error text."""
    result = await client.call_tool(tool, arguments)
    content = result.structured_content
    if result.is_error or not isinstance(content, dict):
        raise CallFailedError(f"{tool}({arguments}) failed: {text_of(result)[:400]}")
    if "job" in content and "result" not in content:
        raise CallFailedError(f"{tool}({arguments}) outlasted the job budget: {content['job']}")
    return content


async def timed_call(client: Client, tool: str, arguments: dict[str, Any], timing: Timing) -> dict[str, Any]:
    began = time.perf_counter()
    content = await call(client, tool, arguments)
    timing.add_s(time.perf_counter() - began)
    return content
