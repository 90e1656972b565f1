"""How a lean profile lists tools, for small models: what a tool does and takes, nothing a model can do
without. Knows no tool; works on any upstream's listing.

- No output schemas (the answers still carry structured content).
- A read-only tool's annotations without ``destructiveHint`` and ``idempotentHint``: the MCP spec gives
  them meaning only when ``readOnlyHint`` is false.
- An argument description that several listed tools repeat word for word (``bag id or name``) is a
  convention: the server instructions state it once, so the listing drops it.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Sequence
from typing import Any

import mcp.types as types

REPEATED_BY_TOOLS = 3  # an argument description this many tools share is a convention


def _argument_descriptions(tool: types.Tool) -> set[tuple[str, str]]:
    properties = tool.input_schema.get("properties", {})
    return {
        (name, body["description"])
        for name, body in properties.items()
        if isinstance(body, dict) and isinstance(body.get("description"), str)
    }


def _without(schema: dict[str, Any], conventions: set[tuple[str, str]]) -> dict[str, Any]:
    properties = schema.get("properties")
    if not isinstance(properties, dict):
        return schema
    kept = {
        name: {k: v for k, v in body.items() if k != "description"}
        if isinstance(body, dict) and (name, body.get("description")) in conventions
        else body
        for name, body in properties.items()
    }
    return {**schema, "properties": kept}


def _annotations(hints: types.ToolAnnotations | None) -> types.ToolAnnotations | None:
    if hints is None or not hints.read_only_hint:
        return hints
    return hints.model_copy(update={"destructive_hint": None, "idempotent_hint": None})


def lean_tools(tools: Sequence[types.Tool]) -> list[types.Tool]:
    counts = Counter(pair for tool in tools for pair in _argument_descriptions(tool))
    conventions = {pair for pair, count in counts.items() if count >= REPEATED_BY_TOOLS}
    return [
        tool.model_copy(
            update={
                "output_schema": None,
                "annotations": _annotations(tool.annotations),
                "input_schema": _without(tool.input_schema, conventions),
            }
        )
        for tool in tools
    ]
