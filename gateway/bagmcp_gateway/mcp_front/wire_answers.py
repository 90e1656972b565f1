"""Tool answers as the gateway relays them: a ``tools/call`` result in its wire form (decoded JSON, camelCase
keys), passed on without being rebuilt as SDK models. Text beyond the cap is cut at a character boundary
with a note saying how to get the rest; structured content is passed on whole (it stays valid JSON)."""

from __future__ import annotations

from typing import Any

from bagmcp_gateway.upstreams.relay import WireResult

DEFAULT_MAX_CHARS = 64_000
NOTE = (
    "\n[answer cut at {kept:,} of {total:,} characters by the gateway; ask for less: a narrower time window, "
    "fewer fields, a smaller limit, or the next page (cursor/offset)]"
)


def _text(block: object) -> str | None:
    if isinstance(block, dict) and block.get("type") == "text" and isinstance(text := block.get("text"), str):
        return text
    return None


def _blocks(result: WireResult) -> list[Any]:
    content = result.get("content")
    return content if isinstance(content, list) else []


def text_characters(result: WireResult) -> int:
    return sum(len(text) for block in _blocks(result) if (text := _text(block)) is not None)


def is_error(result: WireResult) -> bool:
    return result.get("isError") is True


def cap_answer(result: WireResult, *, max_chars: int) -> WireResult:
    total = text_characters(result)
    if total <= max_chars:
        return result
    budget, content = max_chars, []
    for block in _blocks(result):
        text = _text(block)
        if text is None:
            content.append(block)
            continue
        kept = text[: max(budget, 0)]
        budget -= len(kept)
        if kept:
            content.append({**block, "text": kept})
    content.append({"type": "text", "text": NOTE.format(kept=max_chars, total=total)})
    return {**result, "content": content}


def error_result(text: str, **details: object) -> WireResult:
    """A tool error the client sees as ``isError`` (with machine-readable details when given)."""
    result: WireResult = {"content": [{"type": "text", "text": text}], "isError": True}
    if details:
        result["structuredContent"] = details
    return result
