"""A result turned into another shape (a domain result into its report) without copying each field by hand."""

from __future__ import annotations

import dataclasses
from typing import Any, TypeVar, cast

from pydantic import BaseModel

T = TypeVar("T")


def carried(target: type[T], *sources: object, **more: object) -> T:
    """``target`` (a pydantic model or a dataclass) built from ``more`` and, for its other fields, the
    same-named attribute of the first of ``sources`` that has one (a property counts). Pydantic checks each
    value's type, and a field found nowhere fails at once, naming it, so a renamed field cannot pass unseen."""
    shape: Any = target
    names = list(shape.model_fields) if issubclass(target, BaseModel) else [f.name for f in dataclasses.fields(shape)]
    values = dict(more)
    for name in names:
        if name not in values:
            source = next((s for s in sources if s is not None and hasattr(s, name)), None)
            if source is not None:
                values[name] = getattr(source, name)
    return cast(T, shape(**values))
