"""Lean JSON schemas for tools/list: what a model reads on every turn, without pydantic's noise.

Titles go (the property names say it), ``X | None = None`` arguments become plain optional ``X``,
and in output schemas a nullable primitive becomes ``{"type": [X, "null"]}``, defaults go (they say
nothing about an answer) and a definition used once is written where it is used.
"""

from __future__ import annotations

from collections import Counter
from typing import Any

Schema = dict[str, Any]
_NESTED_MAPS = ("properties", "$defs", "definitions")
_NESTED_LISTS = ("anyOf", "oneOf", "allOf", "prefixItems")
_NULL = {"type": "null"}


def _walk(node: Any, *, keep_null: bool, drop: tuple[str, ...] = ("title",)) -> Any:
    """``node`` without the keywords in ``drop`` (properties of those names stay)."""
    if not isinstance(node, dict):
        return node
    out: Schema = {}
    for key, value in node.items():
        if key in drop:
            continue
        if key in _NESTED_MAPS and isinstance(value, dict):
            out[key] = {name: _walk(child, keep_null=keep_null, drop=drop) for name, child in value.items()}
        elif key in _NESTED_LISTS and isinstance(value, list):
            out[key] = [_walk(child, keep_null=keep_null, drop=drop) for child in value]
        elif key in ("items", "additionalProperties"):
            out[key] = _walk(value, keep_null=keep_null, drop=drop)
        else:
            out[key] = value
    return _optional(out, keep_null=keep_null)


def _types_only(options: list[Any]) -> bool:
    return all(isinstance(o, dict) and set(o) == {"type"} and isinstance(o["type"], str) for o in options)


def _optional(node: Schema, *, keep_null: bool) -> Schema:
    options = node.get("anyOf")
    if isinstance(options, list) and _NULL not in options and _types_only(options):
        return {**{k: v for k, v in node.items() if k != "anyOf"}, "type": [o["type"] for o in options]}
    if not isinstance(options, list) or _NULL not in options:
        return node
    others = [o for o in options if o != _NULL]
    rest = {k: v for k, v in node.items() if k != "anyOf"}
    if not keep_null:
        if rest.get("default", 0) is None:
            del rest["default"]
        if len(others) == 1:
            return {**others[0], **rest}
        return {**rest, "type": [o["type"] for o in others]} if _types_only(others) else {**rest, "anyOf": others}
    if _types_only(others):
        return {**rest, "type": [*(o["type"] for o in others), "null"]}
    return node


def _inline_empty_defs(schema: Schema) -> Schema:
    """Definitions that say nothing (``JsonValue`` is ``{}``) are written in place of their references."""
    defs = schema.get("$defs")
    if not isinstance(defs, dict):
        return schema
    empty = {f"#/$defs/{name}" for name, body in defs.items() if body == {}}
    if not empty:
        return schema

    def swap(node: Any) -> Any:
        if isinstance(node, dict):
            if node.get("$ref") in empty:
                return {k: v for k, v in node.items() if k != "$ref"}
            return {k: swap(v) for k, v in node.items()}
        if isinstance(node, list):
            return [swap(v) for v in node]
        return node

    out: Schema = swap({k: v for k, v in schema.items() if k != "$defs"})
    kept = {name: body for name, body in defs.items() if f"#/$defs/{name}" not in empty}
    return {**out, "$defs": swap(kept)} if kept else out


def lean_input(schema: Schema) -> Schema:
    """An input schema without titles, optional arguments as their plain type (no ``default: null``)."""
    lean = _inline_empty_defs(_walk(schema, keep_null=False))
    properties = lean.get("properties")
    if isinstance(properties, dict):
        for prop in properties.values():
            if isinstance(prop, dict) and "default" in prop and prop["default"] is None:
                del prop["default"]
    return lean


def _references(node: Any) -> Counter[str]:
    if isinstance(node, dict):
        found = Counter([node["$ref"]] if isinstance(node.get("$ref"), str) else [])
        return sum((_references(v) for v in node.values()), found)
    if isinstance(node, list):
        return sum((_references(v) for v in node), Counter())
    return Counter()


def _inline_single_use(schema: Schema) -> Schema:
    """Definitions referenced once are written in place of their reference (the name was only a detour).
    A cycle always passes through a definition referenced twice, which stays, so this ends."""
    defs = schema.get("$defs")
    if not isinstance(defs, dict):
        return schema
    counts = _references(schema)
    once = {f"#/$defs/{name}": body for name, body in defs.items() if counts[f"#/$defs/{name}"] == 1}

    def swap(node: Any) -> Any:
        if isinstance(node, dict):
            ref = node.get("$ref")
            if ref in once:
                return {**swap(once[ref]), **{k: swap(v) for k, v in node.items() if k != "$ref"}}
            return {k: swap(v) for k, v in node.items()}
        if isinstance(node, list):
            return [swap(v) for v in node]
        return node

    out: Schema = swap({k: v for k, v in schema.items() if k != "$defs"})
    kept = {name: swap(body) for name, body in defs.items() if f"#/$defs/{name}" not in once}
    return {**out, "$defs": kept} if kept else out


def lean_output(schema: Schema) -> Schema:
    """An output schema without titles or defaults, nullable primitives as a type list (values may still be
    null), each definition used once written in place."""
    return _inline_single_use(_inline_empty_defs(_walk(schema, keep_null=True, drop=("title", "default"))))
