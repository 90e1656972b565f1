"""JSON messages (MCAP ``json`` channels, and the records bagmcp derives from flight logs) as plain types.

The definition is a JSON Schema: ``properties`` become fields (integer -> int64, number -> float64,
boolean, string; objects nest, arrays with ``items`` are sequences). A channel without a schema gets
one inferred from its first message (``infer_schema``). Values of another shape than the schema says are
kept when they convert (an integer where a number is expected) and are None otherwise; a key the
schema does not name is not shown. Decoding costs one ``json.loads`` and one object per nested value.
"""

from __future__ import annotations

import json
from collections.abc import Callable, Mapping

import numpy as np

from bagmcp_shared.bags.plain_types import Builder, ForeignCodec, PlainField, field_name, plain_store

Schema = Mapping[str, object]
Convert = Callable[[object], object]
_BASE = {"integer": "int64", "number": "float64", "boolean": "bool", "string": "string"}
_NUMPY = {"int64": np.int64, "float64": np.float64, "bool": np.bool_}
MAX_DEPTH = 8


def schema_text(title: str, properties: Mapping[str, str]) -> str:
    """A flat JSON Schema with the given property types (what derived records are stored with)."""
    return json.dumps({"title": title, "type": "object", "properties": {k: {"type": v} for k, v in properties.items()}})


def infer_schema(value: object, depth: int = 0) -> dict[str, object]:
    """A JSON Schema that ``value`` (one decoded message) satisfies."""
    if isinstance(value, bool):
        return {"type": "boolean"}
    if isinstance(value, int):
        return {"type": "integer"}
    if isinstance(value, float):
        return {"type": "number"}
    if isinstance(value, list):
        return {"type": "array", "items": infer_schema(value[0], depth + 1) if value else {"type": "string"}}
    if isinstance(value, dict) and depth < MAX_DEPTH:
        return {"type": "object", "properties": {str(k): infer_schema(v, depth + 1) for k, v in value.items()}}
    return {"type": "string"}


def _type_of(schema: Schema) -> str:
    declared = schema.get("type")
    if isinstance(declared, list):
        declared = next((t for t in declared if t != "null"), "string")
    if declared is None and isinstance(schema.get("properties"), dict):
        return "object"
    return str(declared) if declared in (*_BASE, "object", "array") else "string"


def _scalar(kind: str) -> Convert:
    def convert(value: object) -> object:
        if value is None:
            return None
        if kind == "string":
            return value if isinstance(value, str) else json.dumps(value)
        if isinstance(value, bool) != (kind == "bool") or not isinstance(value, int | float):
            return None
        return float(value) if kind == "float64" else int(value) if kind == "int64" else bool(value)

    return convert


def _sequence(kind: str, item: Convert) -> Convert:
    def convert(value: object) -> object:
        if not isinstance(value, list):
            return None
        items = [item(v) for v in value]
        if kind in _NUMPY and all(v is not None for v in items):
            return np.asarray(items, dtype=_NUMPY[kind])
        return items

    return convert


class _Types:
    """Collects the plain types of a schema and the converters from JSON values to builder values."""

    def __init__(self) -> None:
        self.types: dict[str, tuple[PlainField, ...]] = {}

    def message(self, name: str, schema: Schema, depth: int) -> Convert:
        properties = schema.get("properties")
        props = properties if isinstance(properties, Mapping) else {}
        fields: list[PlainField] = []
        converters: list[tuple[str, str, Convert]] = []
        for key, sub in props.items():
            fname = field_name(str(key), [f.name for f in fields])
            field, convert = self.field(f"{name}/{fname}", fname, sub if isinstance(sub, Mapping) else {}, depth)
            fields.append(field)
            converters.append((str(key), fname, convert))
        self.types[name] = tuple(fields)

        def to_values(value: object) -> object:
            if not isinstance(value, Mapping):
                return None
            return {fname: conv(value.get(key)) for key, fname, conv in converters}

        return to_values

    def field(self, nested: str, fname: str, schema: Schema, depth: int) -> tuple[PlainField, Convert]:
        kind = _type_of(schema)
        if kind == "object" and depth < MAX_DEPTH:
            return PlainField(fname, nested), self.message(nested, schema, depth + 1)
        if kind == "array" and depth < MAX_DEPTH:
            items = schema.get("items")
            inner, convert = self.field(nested, fname, items if isinstance(items, Mapping) else {}, depth + 1)
            if inner.size is None:
                return PlainField(fname, inner.kind, 0), _sequence(inner.kind, convert)
        base = _BASE.get(kind, "string")
        return PlainField(fname, base), _scalar(base)


def json_codec(msgtype: str, definition: str) -> ForeignCodec:
    schema = json.loads(definition) if definition.strip() else {}
    if not isinstance(schema, Mapping):
        raise ValueError("the JSON schema is not an object")
    collected = _Types()
    convert = collected.message(msgtype, schema, 0)
    types = tuple(sorted(collected.types.items()))
    store = plain_store(types)
    builder = Builder(store, types)

    def decode(data: bytes) -> object:
        values = convert(json.loads(data))
        if not isinstance(values, Mapping):
            raise ValueError("the message is not a JSON object")
        return builder.build(msgtype, values)

    return ForeignCodec(store, decode)
