"""The MCP side of a run: the gateway's tools as the caller's token lists them, and calls timed one by one.

One ``ToolBox`` is one MCP client session (streamable HTTP, a real socket or an in-process ASGI transport).
Tool answers are kept whole (text, images, structured content); a job answer is followed with ``get_job``
only by ``reference`` (the judge's own calls), never behind a model's back."""

from __future__ import annotations

import json
import time
from collections.abc import AsyncIterator
from contextlib import AsyncExitStack, asynccontextmanager
from dataclasses import dataclass, field
from typing import Any

import anyio
import httpx2
from mcp import Client
from mcp.client.streamable_http import streamable_http_client
from mcp.shared.dispatcher import ProgressFnT
from mcp.types import CallToolResult, ImageContent, TextContent, Tool

from bagmcp_lab.errors import LabError

JOB_POLL_S = 0.2


@dataclass(frozen=True)
class Image:
    mime_type: str
    data_base64: str


@dataclass(frozen=True)
class ToolAnswer:
    """What a tool said: its text (summary and JSON), images, structured content, and whether it failed."""

    name: str
    arguments: dict[str, Any]
    text: str
    images: tuple[Image, ...]
    structured: dict[str, Any] | None
    is_error: bool
    ms: float


def answer_of(name: str, arguments: dict[str, Any], result: CallToolResult, ms: float) -> ToolAnswer:
    texts = [c.text for c in result.content if isinstance(c, TextContent)]
    images = tuple(Image(c.mime_type, c.data) for c in result.content if isinstance(c, ImageContent))
    structured = result.structured_content if isinstance(result.structured_content, dict) else None
    if not texts and structured is not None:
        texts = [json.dumps(structured, separators=(",", ":"))]
    return ToolAnswer(name, arguments, "\n".join(texts), images, structured, bool(result.is_error), ms)


@dataclass
class ToolBox:
    client: Client
    tools: list[Tool] = field(default_factory=list)

    @property
    def instructions(self) -> str | None:
        """What the server tells every client (conventions, units), handed to the model as MCP hosts do."""
        return self.client.instructions

    async def call(self, name: str, arguments: dict[str, Any], *, progress: ProgressFnT | None = None) -> ToolAnswer:
        started = time.perf_counter()
        result = await self.client.call_tool(name, arguments, progress_callback=progress)
        return answer_of(name, arguments, result, (time.perf_counter() - started) * 1000)

    async def reference(self, name: str, **arguments: Any) -> dict[str, Any]:
        """A tool's structured answer for the judge's references (a job is waited for); errors are LabErrors."""
        answer = await self.call(name, arguments)
        if answer.is_error or answer.structured is None:
            raise LabError(f"the reference call {name}({json.dumps(arguments)}) failed: {answer.text[:300]}")
        content = answer.structured
        while "job" in content and isinstance(content["job"], dict):
            await anyio.sleep(JOB_POLL_S)
            job = await self.call("get_job", {"job_id": content["job"]["job_id"]})
            state = (job.structured or {}).get("state")
            if state == "succeeded":
                return dict((job.structured or {})["result"])
            if state not in ("queued", "running"):
                raise LabError(f"the reference call {name} ended as {state}: {job.text[:300]}")
        result = content.get("result", content)
        return dict(result) if isinstance(result, dict) else content


@asynccontextmanager
async def open_toolbox(
    url: str, *, token: str | None, transport: httpx2.AsyncBaseTransport | None = None, timeout_s: float = 300
) -> AsyncIterator[ToolBox]:
    """A session with the MCP server at ``url`` (``transport``: an in-process app instead of a socket)."""
    headers = {"Authorization": f"Bearer {token}"} if token else {}
    http = httpx2.AsyncClient(headers=headers, timeout=httpx2.Timeout(30, read=timeout_s), transport=transport)
    try:
        async with AsyncExitStack() as stack:
            try:
                await stack.enter_async_context(http)
                session = Client(streamable_http_client(url, http_client=http), cache=None)
                client = await stack.enter_async_context(session)
                box = ToolBox(client, list((await client.list_tools()).tools))
            except Exception as err:  # the SDK raises connection and 401 failures as exception groups
                message = f"cannot use the MCP server at {url} ({_first(err)}); check the URL and the token"
                raise LabError(message) from None
            yield box
    except BaseExceptionGroup as group:  # the client's task group wraps what the body raised: unwrap ours
        mine = _first_lab_error(group)
        if mine is None:
            raise
        raise mine from None


def _first_lab_error(group: BaseExceptionGroup[BaseException]) -> LabError | None:
    for err in group.exceptions:
        found = _first_lab_error(err) if isinstance(err, BaseExceptionGroup) else err
        if isinstance(found, LabError):
            return found
    return None


def _first(err: BaseException) -> str:
    while isinstance(err, BaseExceptionGroup) and err.exceptions:
        err = err.exceptions[0]
    return f"{type(err).__name__}: {err}"
