"""PX4 ULog message formats as plain types, and decoding of one ULog data message.

A connection's definition is the log's own format text, one format per line, the message's first and
then every nested format it uses (``vehicle_status:uint64_t timestamp;uint8_t nav_state;...``). Payloads
are packed little-endian in field order; the padding at the end of a top-level format is not stored
(pyulog drops it the same way). ``char[N]`` fields are text; padding fields are read past and hidden.
Decoding one message costs a ``struct.unpack`` and one object per nested value (about 10-30 us).
"""

from __future__ import annotations

import struct
from collections.abc import Callable, Iterator
from itertools import islice

import numpy as np

from bagmcp_shared.bags.plain_types import Builder, ForeignCodec, PlainField, PlainTypes, plain_store

PREFIX = "px4/"
# ULog type -> (struct code, plain base type)
TYPES = {
    "int8_t": ("b", "int8"),
    "uint8_t": ("B", "uint8"),
    "int16_t": ("h", "int16"),
    "uint16_t": ("H", "uint16"),
    "int32_t": ("i", "int32"),
    "uint32_t": ("I", "uint32"),
    "int64_t": ("q", "int64"),
    "uint64_t": ("Q", "uint64"),
    "float": ("f", "float32"),
    "double": ("d", "float64"),
    "bool": ("?", "bool"),
    "char": ("s", "string"),
}
MAX_ARRAY = 0xFFFF
Format = list[tuple[str, int, str]]  # (type, array size or 0, name)
Values = dict[str, object]
Consume = Callable[[Iterator[object]], Values]


def parse_format(line: str) -> tuple[str, Format]:
    """``name:type[N] field;...`` -> the name and its fields."""
    name, _, body = line.partition(":")
    fields: Format = []
    for item in filter(None, (part.strip() for part in body.split(";"))):
        typ, _, field_name = item.partition(" ")
        base, _, rest = typ.partition("[")
        size = int(rest.rstrip("]")) if rest else 0
        if not 0 <= size <= MAX_ARRAY or not field_name:
            raise ValueError(f"field {item!r} of {name} is malformed")
        fields.append((base, size, field_name.strip()))
    if not name:
        raise ValueError(f"format {line[:60]!r} has no name")
    return name, fields


def definition_text(name: str, formats: dict[str, Format]) -> str:
    """The format of ``name`` and of every format it nests, one per line (what a connection stores)."""
    order: list[str] = []
    pending = [name]
    while pending:
        current = pending.pop(0)
        if current in order or current not in formats:
            continue
        order.append(current)
        pending += [typ for typ, _, _ in formats[current] if typ not in TYPES]
    return "\n".join(f"{n}:" + "".join(f"{t}{f'[{s}]' if s else ''} {f};" for t, s, f in formats[n]) for n in order)


def _stored(fields: Format, *, top: bool) -> Format:
    """Fields present in a payload: a top-level format's trailing padding is not logged."""
    kept = list(fields)
    while top and kept and kept[-1][2].startswith("_padding"):
        kept.pop()
    return kept


def _plain(name: str, formats: dict[str, Format]) -> PlainTypes:
    types: dict[str, tuple[PlainField, ...]] = {}
    for fmt_name, fields in formats.items():
        plain = []
        for typ, size, field_name in fields:
            if field_name.startswith("_padding"):
                continue
            if typ == "char":
                plain.append(PlainField(field_name, "string"))
            elif typ in TYPES:
                plain.append(PlainField(field_name, TYPES[typ][1], size or None))
            else:
                plain.append(PlainField(field_name, PREFIX + typ, size or None))
        types[PREFIX + fmt_name] = tuple(plain)
    return tuple(sorted(types.items()))


def _text(raw: object) -> str:
    assert isinstance(raw, bytes)
    return raw.split(b"\0", 1)[0].decode("utf-8", "replace")


class _Layout:
    """The struct format of a format's stored bytes and how to turn the unpacked values into a dict."""

    def __init__(self, formats: dict[str, Format]) -> None:
        self._formats = formats

    def compile(self, name: str, *, top: bool, depth: int = 0) -> tuple[str, Consume]:
        if depth > 16 or name not in self._formats:
            raise ValueError(f"format {name} is missing or nests too deeply")
        parts: list[str] = []
        steps: list[Callable[[Iterator[object], Values], None]] = []
        for typ, size, field_name in _stored(self._formats[name], top=top):
            code, step = self._field(typ, size, field_name, depth)
            parts.append(code)
            if step is not None:
                steps.append(step)

        def consume(values: Iterator[object]) -> Values:
            out: Values = {}
            for step in steps:
                step(values, out)
            return out

        return "".join(parts), consume

    def _field(
        self, typ: str, size: int, name: str, depth: int
    ) -> tuple[str, Callable[[Iterator[object], Values], None] | None]:
        if name.startswith("_padding"):
            width = (size or 1) * (struct.calcsize(TYPES[typ][0]) if typ in TYPES and typ != "char" else 1)
            return f"{width}x", None
        if typ == "char":
            return f"{size or 1}s", lambda it, out: out.__setitem__(name, _text(next(it)))
        if typ in TYPES:
            code, kind = TYPES[typ]
            if not size:
                return code, lambda it, out: out.__setitem__(name, next(it))
            dtype = np.dtype(kind if kind != "bool" else np.bool_)
            return f"{size}{code}", lambda it, out: out.__setitem__(name, np.array(list(islice(it, size)), dtype))
        inner_code, inner = self.compile(typ, top=False, depth=depth + 1)
        if not size:
            return inner_code, lambda it, out: out.__setitem__(name, inner(it))
        return inner_code * size, lambda it, out: out.__setitem__(name, [inner(it) for _ in range(size)])


def ulog_codec(msgtype: str, definition: str) -> ForeignCodec:
    formats = dict(parse_format(line) for line in definition.splitlines() if line.strip())
    name = msgtype.removeprefix(PREFIX)
    types = _plain(name, formats)
    store = plain_store(types)
    builder = Builder(store, types)
    code, consume = _Layout(formats).compile(name, top=True)
    layout = struct.Struct("<" + code)

    def decode(data: bytes) -> object:
        values = layout.unpack_from(data)
        return builder.build(msgtype, consume(iter(values)))

    return ForeignCodec(store, decode)
