"""Decoded messages as JSON-ready values, cut to a bounded size for an LLM's context."""

from __future__ import annotations

import json
import math
from dataclasses import dataclass

import numpy as np

Json = None | bool | int | float | str | list["Json"] | dict[str, "Json"]


@dataclass(frozen=True)
class Limits:
    """How much of a message to show: items per array and characters per string."""

    max_items: int = 64
    max_text: int = 2000


# From generous to terse: ``fit`` takes the first that fits the byte budget.
LADDER = (Limits(64, 2000), Limits(16, 400), Limits(4, 120), Limits(1, 40))


def _number(value: float) -> float | str:
    return value if math.isfinite(value) else str(value)


def _text(value: str, limits: Limits) -> str:
    if len(value) <= limits.max_text:
        return value
    return f"{value[: limits.max_text]}... ({len(value)} characters in all)"


def _array(values: np.ndarray, limits: Limits) -> Json:
    if values.dtype == np.uint8 and values.size > limits.max_items:
        return {"_bytes": int(values.size), "_first": [int(v) for v in values[:16]]}
    items = [_convert(v.item(), limits) for v in values[: limits.max_items]]
    if values.size <= limits.max_items:
        return items
    return {"_length": int(values.size), "_first": items, "_truncated": True}


def _convert(value: object, limits: Limits) -> Json:
    if value is None or isinstance(value, bool | int):
        return value
    if isinstance(value, str):
        return _text(value, limits)
    if isinstance(value, float):
        return _number(value)
    if isinstance(value, np.ndarray):
        return _array(value, limits)
    if isinstance(value, np.generic):
        return _convert(value.item(), limits)
    if isinstance(value, bytes | bytearray):
        return {"_bytes": len(value)}
    if isinstance(value, list | tuple):
        items = [_convert(v, limits) for v in value[: limits.max_items]]
        if len(value) <= limits.max_items:
            return items
        return {"_length": len(value), "_first": items, "_truncated": True}
    if isinstance(value, dict):
        return {str(key): _convert(item, limits) for key, item in value.items()}
    fields = getattr(value, "__dataclass_fields__", None)
    if isinstance(fields, dict):
        return {name: _convert(getattr(value, name), limits) for name in fields if not name.startswith("__")}
    return _text(str(value), limits)


def to_json(value: object, *, max_items: int = 64, max_text: int = 2000) -> Json:
    """Plain JSON for a decoded message or any part of it.

    Arrays longer than ``max_items`` become ``{"_length", "_first", "_truncated"}``; byte blobs
    (images) become ``{"_bytes", "_first"}``; strings longer than ``max_text`` are cut with a note;
    NaN and infinities become strings.
    """
    return _convert(value, Limits(max_items, max_text))


def fit(value: object, budget_bytes: int) -> Json:
    """``value`` as JSON within ``budget_bytes``, shown less fully the larger it is."""
    for limits in LADDER:
        converted = _convert(value, limits)
        if len(json.dumps(converted)) <= budget_bytes:
            return converted
    return {"_omitted": f"too large to show within {budget_bytes} bytes; project fields with `fields`"}
