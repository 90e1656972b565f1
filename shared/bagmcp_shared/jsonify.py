"""Decoded messages as JSON-ready values, with long arrays cut to a bounded size."""

from __future__ import annotations

import math

import numpy as np

Json = None | bool | int | float | str | list["Json"] | dict[str, "Json"]


def _number(value: float) -> float | str:
    return value if math.isfinite(value) else str(value)


def _array(values: np.ndarray, max_items: int) -> Json:
    if values.dtype == np.uint8 and values.size > max_items:
        return {"_bytes": int(values.size), "_first": [int(v) for v in values[:16]]}
    items = [to_json(v.item(), max_items=max_items) for v in values[:max_items]]
    if values.size <= max_items:
        return items
    return {"_length": int(values.size), "_first": items, "_truncated": True}


def to_json(value: object, *, max_items: int = 64) -> Json:
    """Plain JSON for a decoded message or any part of it.

    Arrays longer than ``max_items`` become ``{"_length", "_first", "_truncated"}``; byte
    blobs (images) become ``{"_bytes", "_first"}``; NaN and infinities become strings.
    """
    if value is None or isinstance(value, bool | int | str):
        return value
    if isinstance(value, float):
        return _number(value)
    if isinstance(value, np.ndarray):
        return _array(value, max_items)
    if isinstance(value, np.generic):
        return to_json(value.item(), max_items=max_items)
    if isinstance(value, bytes | bytearray):
        return {"_bytes": len(value)}
    if isinstance(value, list | tuple):
        items = [to_json(v, max_items=max_items) for v in value[:max_items]]
        if len(value) <= max_items:
            return items
        return {"_length": len(value), "_first": items, "_truncated": True}
    fields = getattr(value, "__dataclass_fields__", None)
    if isinstance(fields, dict):
        return {
            name: to_json(getattr(value, name), max_items=max_items) for name in fields if not name.startswith("__")
        }
    return str(value)
