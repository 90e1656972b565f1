"""Filtered copies of recordings whose messages are not ROS messages (flight logs, non-ROS MCAP), written
as MCAP with JSON messages and one JSON Schema per topic.

A ULog or DataFlash file cannot be rewritten in its own format from a selection of topics, and its
payloads mean nothing to a ROS reader; JSON MCAP keeps every field with its name and type, opens in
Foxglove and PlotJuggler, and is read back by bagmcp itself. Values are the decoded ones (DataFlash
multipliers applied); NaN and infinities become null (JSON has no such numbers). Converting costs the
decoding plus ``json.dumps`` (about 30 us for a 50-field message).
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import BinaryIO

import numpy as np
from mcap.writer import CompressionType, Writer
from rosbags.interfaces import Nodetype
from rosbags.typesys.store import Typestore

from bagmcp_shared.bags.models import Connection, RawMessage
from bagmcp_shared.bags.reader import BagReader
from bagmcp_shared.bags.writer_connections import Convert, OutConn

_JSON_TYPES = {"bool": "boolean", "string": "string", "float32": "number", "float64": "number"}


def _schema_of(store: Typestore, node: tuple[object, ...], depth: int = 0) -> dict[str, object]:
    kind, detail = node
    if kind == Nodetype.NAME and depth < 16:
        return json_schema(store, str(detail), depth + 1)
    if kind in (Nodetype.ARRAY, Nodetype.SEQUENCE) and isinstance(detail, tuple):
        return {"type": "array", "items": _schema_of(store, tuple(detail[0]), depth + 1)}
    base = str(detail[0]) if isinstance(detail, tuple) else str(detail)
    return {"type": _JSON_TYPES.get(base, "integer" if "int" in base else "string")}


def json_schema(store: Typestore, msgtype: str, depth: int = 0) -> dict[str, object]:
    """The JSON Schema of a registered type (what a JSON MCAP channel of it declares)."""
    fields = store.fielddefs[msgtype][1]
    return {
        "title": msgtype,
        "type": "object",
        "properties": {name: _schema_of(store, tuple(node), depth) for name, node in fields},
    }


def plain_value(value: object) -> object:
    """A decoded message (or part of it) as plain JSON values, in full."""
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, np.ndarray):
        return [plain_value(v) for v in value.tolist()]
    if isinstance(value, np.generic):
        return plain_value(value.item())
    if isinstance(value, list | tuple):
        return [plain_value(v) for v in value]
    if isinstance(value, bytes | bytearray):
        return list(value)
    names = getattr(value, "__dataclass_fields__", None)
    if isinstance(names, dict):
        return {n: plain_value(getattr(value, n)) for n in names if not n.startswith("__")}
    return value


def json_output(reader: BagReader, conn: Connection) -> tuple[OutConn, Convert]:
    """The output connection (msgdef: its JSON Schema) and the payload conversion of ``conn``."""
    store = reader.decoder.typestore(conn.msgtype)
    schema = json.dumps(json_schema(store, conn.msgtype))

    def convert(data: bytes) -> bytes:
        message = reader.decode(RawMessage(conn, 0, data))
        return json.dumps(plain_value(message), separators=(",", ":")).encode()

    return OutConn(conn.topic, conn.msgtype, schema, "", metadata=conn.metadata), convert


class JsonMcapWriter:
    """The few calls the filtered-bag writer makes (open, add_connection, write, close, abort) on a
    JSON MCAP file with zstd chunks."""

    def __init__(self, path: Path) -> None:
        self.path = path
        self._file: BinaryIO | None = None
        self._writer: Writer | None = None
        self._schemas: dict[tuple[str, str], int] = {}

    def open(self) -> None:
        self._file = self.path.open("xb")
        self._writer = Writer(self._file, compression=CompressionType.ZSTD)
        self._writer.start(profile="", library="bagmcp")

    def add_connection(self, out: OutConn) -> int:
        assert self._writer is not None
        key = (out.msgtype, out.msgdef)
        if key not in self._schemas:
            self._schemas[key] = self._writer.register_schema(out.msgtype, "jsonschema", out.msgdef.encode())
        return self._writer.register_channel(out.topic, "json", self._schemas[key], dict(out.metadata))

    def write(self, channel: int, log_time_ns: int, data: bytes | memoryview) -> None:
        assert self._writer is not None
        self._writer.add_message(channel, log_time_ns, bytes(data), log_time_ns)

    def close(self) -> None:
        assert self._writer is not None
        assert self._file is not None
        self._writer.finish()  # type: ignore[no-untyped-call]
        self._file.close()

    def abort(self) -> None:
        if self._file is not None:
            self._file.close()
