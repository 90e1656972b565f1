"""data_tamer messages (MCAP profile ``data_tamer``, PlotJuggler's logging library) as plain types.

The schema is text: ``### key: value`` header lines, then one ``type name`` field per line (``T[]`` a
sequence with a uint32 length, ``T[N]`` a fixed array), then nested types after ``=====`` lines, each
starting ``MSG: Name``. A payload is a uint32 mask length, the mask (bit i of byte i/8 set when the
i-th top-level field was sampled), a uint32 payload length and the sampled fields, packed little-endian.
A field that was not sampled is None. Decoding walks the bytes once (about 20 us for 10 fields).
"""

from __future__ import annotations

import struct
from collections.abc import Callable

import numpy as np

from bagmcp_shared.bags.plain_types import Builder, ForeignCodec, PlainField, field_name, plain_store, type_name

_BASE = {
    "bool": "?",
    "char": "b",
    "int8": "b",
    "uint8": "B",
    "int16": "h",
    "uint16": "H",
    "int32": "i",
    "uint32": "I",
    "int64": "q",
    "uint64": "Q",
    "float32": "f",
    "float64": "d",
}
_PLAIN = {"char": "int8"}
Field = tuple[str, int | None, str]  # type, size (None one, 0 sequence, N fixed), name
Read = Callable[[memoryview, int], tuple[object, int]]


def parse_schema(text: str) -> tuple[list[Field], dict[str, list[Field]]]:
    """The top-level fields and the nested types of a schema."""
    sections = [s for s in text.split("\n=") if s.strip()]
    top = _fields(sections[0]) if sections else []
    nested: dict[str, list[Field]] = {}
    for section in sections[1:]:
        lines = [line for line in section.splitlines() if line.strip() and not line.startswith("=")]
        if not lines or not lines[0].startswith("MSG:"):
            raise ValueError("a nested type does not start with 'MSG: Name'")
        nested[lines[0].removeprefix("MSG:").strip()] = _fields("\n".join(lines[1:]))
    return top, nested


def _fields(text: str) -> list[Field]:
    found: list[Field] = []
    for line in text.splitlines():
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        typ, _, name = line.partition(" ")
        base, bracket, rest = typ.partition("[")
        size = (int(rest.rstrip("]")) if rest.rstrip("]") else 0) if bracket else None
        found.append((base, size, name.strip()))
    return found


class _Reader:
    def __init__(self, nested: dict[str, list[Field]], prefix: str) -> None:
        self._nested = nested
        self.prefix = prefix
        self.types: dict[str, tuple[PlainField, ...]] = {}

    def message(self, name: str, fields: list[Field], depth: int = 0) -> list[tuple[str, Read]]:
        if depth > 16:
            raise ValueError(f"type {name} nests too deeply")
        readers: list[tuple[str, Read]] = []
        plain: list[PlainField] = []
        for typ, size, raw_name in fields:
            fname = field_name(raw_name, [p.name for p in plain])
            read, kind = self._field(typ, size, depth)
            plain.append(PlainField(fname, kind, size))
            readers.append((fname, read))
        self.types[name] = tuple(plain)
        return readers

    def _field(self, typ: str, size: int | None, depth: int) -> tuple[Read, str]:
        if typ in _BASE:
            one = struct.Struct("<" + _BASE[typ])
            kind = _PLAIN.get(typ, typ)
            return _array(size, lambda buf, at: (one.unpack_from(buf, at)[0], at + one.size), kind), kind
        if typ not in self._nested:
            raise ValueError(f"type {typ} is not defined in the schema")
        msgtype = f"{self.prefix}/{type_name(typ)}"
        inner = self.message(msgtype, self._nested[typ], depth + 1)

        def read(buf: memoryview, at: int) -> tuple[object, int]:
            out: dict[str, object] = {}
            for fname, reader in inner:
                out[fname], at = reader(buf, at)
            return out, at

        return _array(size, read, None), msgtype


def _array(size: int | None, one: Read, kind: str | None) -> Read:
    if size is None:
        return one

    def read(buf: memoryview, at: int) -> tuple[object, int]:
        count = size
        if not count:
            (count,) = struct.unpack_from("<I", buf, at)
            at += 4
            if count > len(buf):
                raise ValueError(f"a sequence claims {count} items in a {len(buf)}-byte message")
        items = []
        for _ in range(count):
            item, at = one(buf, at)
            items.append(item)
        return (np.asarray(items, dtype=np.dtype(kind if kind != "bool" else np.bool_)) if kind else items), at

    return read


def data_tamer_codec(msgtype: str, definition: str) -> ForeignCodec:
    top, nested = parse_schema(definition)
    reader = _Reader(nested, msgtype)
    fields = reader.message(msgtype, top)
    types = tuple(sorted(reader.types.items()))
    store = plain_store(types)
    builder = Builder(store, types)

    def decode(data: bytes) -> object:
        buf = memoryview(data)
        (mask_size,) = struct.unpack_from("<I", buf, 0)
        mask = bytes(buf[4 : 4 + mask_size])
        (payload_size,) = struct.unpack_from("<I", buf, 4 + mask_size)
        at = 8 + mask_size
        if at + payload_size > len(buf):
            raise ValueError(f"the payload claims {payload_size} bytes but {len(buf) - at} remain")
        values: dict[str, object] = {}
        for number, (fname, read) in enumerate(fields):
            sampled = number // 8 < len(mask) and mask[number // 8] >> (number % 8) & 1
            values[fname], at = read(buf, at) if sampled else (None, at)
        return builder.build(msgtype, values)

    return ForeignCodec(store, decode)
