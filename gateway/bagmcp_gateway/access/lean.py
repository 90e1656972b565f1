"""How a lean profile lists tools, for small models: what a tool does and takes, nothing a model can do
without. Knows no tool; works on any upstream's listing.

- No output schemas (the answers still carry structured content).
- No annotations: they are hints for clients (which ask a person before a write), not for the model, and a
  lean listing is for a model's context; a client that shows them uses the full profile.
- No tuning knobs: an optional argument with a default value (``limit: 20``, ``style: "line"``) is left
  out of the listing; the tool still takes it, and small models do best with the default. Optional
  arguments without a default (``topic``, ``start``) stay: they change what is asked.
- An argument description that several listed tools repeat word for word (``bag id or name``, ``s from
  start, or ISO``, ``default: the obvious one``) is a convention: the server instructions state it once,
  so the listing drops it.

Measured on the core profile's 12 tools (2026-11-27): 7,649 characters of tools/list with output schemas
dropped alone; knobs -536, annotations -560.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Sequence
from typing import Any

import mcp.types as types

REPEATED_BY_TOOLS = 3  # an argument description this many tools share is a convention


def _argument_descriptions(tool: types.Tool) -> set[str]:
    properties = tool.input_schema.get("properties", {})
    return {
        body["description"]
        for body in properties.values()
        if isinstance(body, dict) and isinstance(body.get("description"), str)
    }


def _knob(name: str, body: object, required: list[str]) -> bool:
    return isinstance(body, dict) and name not in required and body.get("default") is not None


def _without(schema: dict[str, Any], conventions: set[str]) -> dict[str, Any]:
    properties = schema.get("properties")
    if not isinstance(properties, dict):
        return schema
    required = list(schema.get("required") or [])
    kept = {
        name: {k: v for k, v in body.items() if k != "description"}
        if isinstance(body, dict) and body.get("description") in conventions
        else body
        for name, body in properties.items()
        if not _knob(name, body, required)
    }
    return {**schema, "properties": kept}


def lean_tools(tools: Sequence[types.Tool]) -> list[types.Tool]:
    counts = Counter(text for tool in tools for text in _argument_descriptions(tool))
    conventions = {text for text, count in counts.items() if count >= REPEATED_BY_TOOLS}
    return [
        tool.model_copy(
            update={
                "output_schema": None,
                "annotations": None,
                "input_schema": _without(tool.input_schema, conventions),
            }
        )
        for tool in tools
    ]
