"""Capping what a tool call returns: text beyond the cap is cut at a character boundary with a note
saying how to get the rest; structured content is passed on whole (it stays valid JSON)."""

from __future__ import annotations

import mcp.types as types

DEFAULT_MAX_CHARS = 64_000
NOTE = (
    "\n[answer cut at {kept:,} of {total:,} characters by the gateway; ask for less: a narrower time window, "
    "fewer fields, a smaller limit, or the next page (cursor/offset)]"
)


def cap_answer(result: types.CallToolResult, *, max_chars: int) -> types.CallToolResult:
    texts = [c for c in result.content if isinstance(c, types.TextContent)]
    total = sum(len(c.text) for c in texts)
    if total <= max_chars:
        return result
    budget, content = max_chars, list[types.ContentBlock]()
    for block in result.content:
        if isinstance(block, types.TextContent):
            kept = block.text[: max(budget, 0)]
            budget -= len(kept)
            if kept:
                content.append(block.model_copy(update={"text": kept}))
        else:
            content.append(block)
    content.append(types.TextContent(type="text", text=NOTE.format(kept=max_chars, total=total)))
    return result.model_copy(update={"content": content})


def error_result(text: str, **details: object) -> types.CallToolResult:
    """A tool error the client sees as ``is_error`` (with machine-readable details when given)."""
    return types.CallToolResult(
        content=[types.TextContent(type="text", text=text)], is_error=True, structured_content=details or None
    )
