"""Message types that are not ROS types (ULog formats, DataFlash FMT records, JSON schemas, protobuf
descriptors, data_tamer schemas) registered as rosbags types.

Message paths, ``describe_topic``, search and the JSON answers all walk rosbags typestores and the
dataclasses they generate; registering the foreign types the same way lets every one of them work on
flight logs and non-ROS MCAP without a second code path. Registering a type costs about 0.1 ms; the
stores are kept per set of definitions (``plain_store``), so a bag opened again pays nothing.
"""

from __future__ import annotations

import functools
import keyword
import re
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass
from dataclasses import field as dataclass_field
from typing import Any

from rosbags.interfaces import Nodetype
from rosbags.typesys import Stores, get_typestore
from rosbags.typesys.store import Typestore

BASE_TYPES = frozenset(
    {"bool", "int8", "uint8", "int16", "uint16", "int32", "uint32", "int64", "uint64", "float32", "float64", "string"}
)
_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")


@dataclass(frozen=True)
class PlainField:
    """One field: ``kind`` is a base type (``BASE_TYPES``) or another plain message type's name;
    ``size`` None is a single value, 0 a sequence of any length, N a fixed array of N."""

    name: str
    kind: str
    size: int | None = None

    @property
    def nested(self) -> bool:
        return self.kind not in BASE_TYPES


@dataclass(frozen=True)
class ForeignCodec:
    """How one non-ROS type decodes: ``decode`` makes a message object (a dataclass of ``store``) from a
    payload; ``units`` maps field paths to the units the type's definition gives them."""

    store: Typestore
    decode: Callable[[bytes], object]
    units: Mapping[str, str] = dataclass_field(default_factory=dict)


PlainTypes = tuple[tuple[str, tuple[PlainField, ...]], ...]  # (msgtype, fields), hashable for caching


def field_name(text: str, taken: Iterable[str] = ()) -> str:
    """A field name message paths accept (letters, digits, '_', not a keyword, not starting '__')."""
    name = re.sub(r"[^A-Za-z0-9_]", "_", text) or "field"
    if not _NAME.fullmatch(name) or name.startswith("__"):
        name = f"f_{name.lstrip('_')}"
    if keyword.iskeyword(name):
        name = f"{name}_"
    used = set(taken)
    unique, number = name, 2
    while unique in used:
        unique, number = f"{name}_{number}", number + 1
    return unique


def type_name(text: str) -> str:
    """A message type name rosbags accepts (identifier parts joined by '/') for a foreign schema name:
    ``foxglove.PoseInFrame`` -> ``foxglove/PoseInFrame``, ``channelA::1757`` -> ``channelA/n1757``."""
    parts = [p if not p[0].isdigit() else f"n{p}" for p in re.split(r"[^A-Za-z0-9_]+", text) if p.strip("_")]
    return "/".join(parts) or "unnamed"


def _node(field: PlainField) -> tuple[Any, ...]:
    inner: tuple[Any, ...] = (Nodetype.NAME, field.kind) if field.nested else (Nodetype.BASE, (field.kind, 0))
    if field.size is None:
        return inner
    if field.size == 0:
        return (Nodetype.SEQUENCE, (inner, 0))
    return (Nodetype.ARRAY, (inner, field.size))


@functools.lru_cache(maxsize=256)
def plain_store(types: PlainTypes) -> Typestore:
    """A typestore holding exactly ``types`` (nested types must be among them)."""
    store = get_typestore(Stores.EMPTY)
    store.register({name: ([], [(f.name, _node(f)) for f in fields]) for name, fields in types})
    return store


Values = Mapping[str, object]


class Builder:
    """Makes message objects (the store's dataclasses) from plain values: a dict per message, lists of
    dicts for arrays of nested types; base values and numpy arrays are used as they are. A field
    missing from the values is None (e.g. a JSON key that a message leaves out)."""

    def __init__(self, store: Typestore, types: PlainTypes) -> None:
        self._store = store
        self._fields = dict(types)
        self._makers: dict[str, Callable[[Values], object]] = {}

    def build(self, msgtype: str, values: Values) -> object:
        maker = self._makers.get(msgtype)
        if maker is None:
            maker = self._makers[msgtype] = self._maker(msgtype)
        return maker(values)

    def cls(self, msgtype: str) -> Callable[..., object]:
        """The dataclass of ``msgtype``: called with every field's value in field order."""
        made: Callable[..., object] = self._store.types[msgtype]
        return made

    def _maker(self, msgtype: str) -> Callable[[Values], object]:
        cls = self.cls(msgtype)
        fields = self._fields[msgtype]
        names = [f.name for f in fields]
        nested = [f for f in fields if f.nested]
        if not nested:
            return lambda values: cls(*map(values.get, names))

        def make(values: Values) -> object:
            given = dict(values)
            for f in nested:
                given[f.name] = self._value(f, given.get(f.name))
            return cls(*map(given.get, names))

        return make

    def _value(self, field: PlainField, value: object) -> object:
        if value is None:
            return None
        if field.size is None:
            return self.build(field.kind, value) if isinstance(value, Mapping) else None
        items = value if isinstance(value, list | tuple) else []
        return [self.build(field.kind, item) if isinstance(item, Mapping) else None for item in items]
