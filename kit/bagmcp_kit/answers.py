"""Answer conventions: structured content plus a short text summary, and errors as tool errors
(``is_error``) whose sentence says what to do next. The one place BagmcpError becomes a tool error."""

from __future__ import annotations

import json
from collections.abc import Iterator
from contextlib import contextmanager

from mcp.server.mcpserver.exceptions import ToolError
from mcp.types import CallToolResult, ContentBlock, TextContent
from pydantic import BaseModel

from bagmcp_shared.errors import BagmcpError, sentence


@contextmanager
def tool_errors() -> Iterator[None]:
    """Turn the project's errors into tool errors; anything else stays an internal error."""
    try:
        yield
    except BagmcpError as err:
        raise ToolError(sentence(err)) from err


def answer(
    model: BaseModel, summary: str, *, extra: list[ContentBlock] | None = None, omit_none: bool = False
) -> CallToolResult:
    """The model as structured content, and as text: a one-line summary, then the JSON.

    ``omit_none`` leaves out top-level fields that are None (for models whose such fields have defaults)."""
    data = model.model_dump(mode="json")
    if omit_none:
        data = {key: value for key, value in data.items() if value is not None}
    text = f"{summary}\n{json.dumps(data, separators=(',', ':'))}"
    content: list[ContentBlock] = [TextContent(type="text", text=text), *(extra or [])]
    return CallToolResult(content=content, structured_content=data)
