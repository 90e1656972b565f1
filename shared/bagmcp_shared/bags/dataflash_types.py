"""ArduPilot DataFlash message types (FMT records) as plain types, and decoding of one record body.

A connection's definition is JSON: the type's name, FMT format characters, column names and units (from
FMTU/UNIT/MULT, as pymavlink names them). Values follow pymavlink's DFReader: the format characters'
own multipliers are applied (``L`` latitude/longitude to degrees, ``c``/``C``/``e``/``E`` hundredths),
text is cut at its first NUL, ``a`` is an array of 32 int16. Units stay as the log states them: a field
whose FMTU multiplier is not applied by its format character keeps the prefixed unit (``cA``, ``us``).
"""

from __future__ import annotations

import json
import struct
from collections.abc import Callable

import numpy as np
from pymavlink.DFReader import FORMAT_TO_STRUCT  # type: ignore[import-untyped]

from bagmcp_shared.bags.plain_types import Builder, ForeignCodec, PlainField, field_name, plain_store

PREFIX = "ardupilot/"
_TEXT = frozenset("nNZ")
_FLOATS = frozenset("fdgcCeEL")
_INTS = {"b": "int8", "B": "uint8", "h": "int16", "H": "uint16", "i": "int32", "I": "uint32", "M": "int8"}
_INTS |= {"q": "int64", "Q": "uint64"}


def definition_json(name: str, fmt: str, columns: list[str], units: list[str]) -> str:
    return json.dumps({"name": name, "format": fmt, "columns": columns, "units": units})


def _kind(code: str) -> tuple[str, int | None]:
    if code in _TEXT:
        return "string", None
    if code == "a":
        return "int16", 32
    if code in _FLOATS:
        return "float64" if code != "f" else "float32", None
    return _INTS[code], None


def _text(raw: bytes) -> str:
    cut = raw.split(b"\0", 1)[0]
    try:
        return cut.decode("utf-8")
    except UnicodeDecodeError:
        return cut.decode("ISO-8859-1")


def _converter(code: str) -> Callable[[object], object]:
    multiplier = FORMAT_TO_STRUCT[code][1]
    if code in _TEXT:
        return lambda v: _text(v)  # type: ignore[arg-type]
    if code == "a":
        return lambda v: np.frombuffer(v, dtype="<i2").copy()  # type: ignore[call-overload]
    if multiplier is not None and 0 < multiplier < 1:
        divisor = 1 / multiplier  # pymavlink divides: 1e7 gives exact degrees where 1e-7 would not
        return lambda v: float(v) / divisor  # type: ignore[arg-type]
    if code in _FLOATS:
        return lambda v: float(v)  # type: ignore[arg-type]
    return lambda v: v


def dataflash_codec(msgtype: str, definition: str) -> ForeignCodec:
    spec = json.loads(definition)
    fmt, columns, units = str(spec["format"]), [str(c) for c in spec["columns"]], [str(u) for u in spec["units"]]
    if len(fmt) != len(columns):
        raise ValueError(f"{spec['name']}: {len(fmt)} format characters for {len(columns)} columns")
    names: list[str] = []
    for column in columns:
        names.append(field_name(column, names))
    fields = tuple(PlainField(n, *_kind(code)) for n, code in zip(names, fmt, strict=True))
    types = ((msgtype, fields),)
    store = plain_store(types)
    builder = Builder(store, types)
    codes = "".join("64s" if code == "a" else FORMAT_TO_STRUCT[code][0] for code in fmt)
    layout = struct.Struct("<" + codes)
    converted = [(i, _converter(code)) for i, code in enumerate(fmt) if code in _TEXT or code in _FLOATS or code == "a"]
    make = builder.cls(msgtype)

    def decode(data: bytes) -> object:
        values = list(layout.unpack_from(data))
        for i, convert in converted:
            values[i] = convert(values[i])
        return make(*values)

    unit_of = {n: u for n, u in zip(names, units, strict=False) if u}
    return ForeignCodec(store, decode, unit_of)
