"""Building the columnar index at ingest: one pass over the bag extracts the numeric columns of common
types, the TF transforms and the log records, into one directory with a versioned manifest."""

from __future__ import annotations

import json
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import cast

import numpy as np

from bagmcp_shared.bags import BagReader, RawMessage
from bagmcp_shared.errors import BagmcpError
from bagmcp_shared.flight_types import flight_columns
from bagmcp_shared.index.columns import INDEXED_COLUMNS
from bagmcp_shared.index.logs import RECORD_TYPES, LogRow, log_row, save_logs
from bagmcp_shared.index.series import Collector, header_rate_hz
from bagmcp_shared.index.transforms import TF_TYPES, TransformCollector, is_static, save_transforms

MANIFEST = "manifest.json"
FORMAT_VERSION = 4  # bump when the files change; older indexes are then ignored and rebuilt
Progress = Callable[[float, str], None]


def slug(topic: str) -> str:
    return topic.strip("/").replace("/", "__") or "_root"


@dataclass
class _Extracts:
    columns: dict[str, Collector] = field(default_factory=dict)
    transforms: dict[str, TransformCollector] = field(default_factory=dict)
    static: dict[int, bool] = field(default_factory=dict)
    logs: dict[str, list[LogRow]] = field(default_factory=dict)
    skipped: dict[str, str] = field(default_factory=dict)

    def topics(self) -> list[str]:
        return sorted({*self.columns, *self.transforms, *self.logs})

    def add(self, raw: RawMessage, message: object) -> None:
        topic = raw.connection.topic
        if topic in self.columns:
            self.columns[topic].add(raw, message)
        if topic in self.transforms:
            self.transforms[topic].add(raw.log_time_ns, message, static=self.static.get(raw.connection.id, False))
        if topic in self.logs:
            self.logs[topic].append(log_row(raw.log_time_ns, message))


def _extracts(reader: BagReader) -> _Extracts:
    """What to extract from each topic whose type the index covers and whose definition decodes."""
    found = _Extracts()
    for conn in reader.connections:
        if not conn.count or conn.msgtype in reader.decoder.problems:
            continue
        columns = INDEXED_COLUMNS.get(conn.msgtype) or flight_columns(
            reader.decoder.typestore(conn.msgtype), conn.msgtype
        )
        if columns:
            try:
                found.columns.setdefault(conn.topic, Collector(reader, conn.topic, columns))
            except BagmcpError:
                continue  # a same-named type with another definition: left to decoding
        if conn.msgtype in TF_TYPES:
            found.transforms.setdefault(conn.topic, TransformCollector())
            found.static[conn.id] = is_static(conn)
        if conn.msgtype in RECORD_TYPES:
            found.logs.setdefault(conn.topic, [])
    return found


def _write(found: _Extracts, directory: Path) -> dict[str, object]:
    columns: dict[str, dict[str, object]] = {}
    for topic, collector in found.columns.items():
        series = collector.series("index")
        arrays = {f"c:{k}": v for k, v in series.columns.items()}
        name = f"{slug(topic)}.npz"
        cast(Callable[..., None], np.savez)(directory / name, t_ns=series.t_ns, header_ns=series.header_ns, **arrays)
        columns[topic] = {
            "file": name,
            "columns": collector.names,
            "count": len(series.t_ns),
            "header_rate_hz": header_rate_hz(series.header_ns),
        }
    transforms: dict[str, dict[str, object]] = {}
    for topic, tf in found.transforms.items():
        rows = tf.rows_out()
        save_transforms(rows, str(directory / f"{slug(topic)}.tf.npz"))
        transforms[topic] = {"file": f"{slug(topic)}.tf.npz", "count": len(rows)}
    logs: dict[str, dict[str, object]] = {}
    for topic, records in found.logs.items():
        save_logs(records, directory / f"{slug(topic)}.logs.json")
        logs[topic] = {"file": f"{slug(topic)}.logs.json", "count": len(records)}
    return {"topics": columns, "transforms": transforms, "logs": logs}


def build_index(reader: BagReader, directory: Path, progress: Progress | None = None) -> dict[str, object]:
    """Extract every indexed topic into ``directory`` in one pass; returns the manifest.

    A topic with a message that does not decode is left out of the index (its questions are then
    answered by decoding, which reports the problem).
    """
    directory.mkdir(parents=True, exist_ok=True)
    found = _extracts(reader)
    topics = found.topics()
    total = max(sum(c.count for c in reader.connections if c.topic in topics), 1)
    for number, raw in enumerate(reader.messages(topics)):
        topic = raw.connection.topic
        if topic in found.skipped:
            continue
        try:
            found.add(raw, reader.decode(raw))
        except BagmcpError as err:
            found.skipped[topic] = str(err)
        if progress is not None and number % 5000 == 0:
            progress(number / total, "indexing")
    for topic in found.skipped:
        for table in (found.columns, found.transforms, found.logs):
            table.pop(topic, None)
    document = {"version": FORMAT_VERSION, **_write(found, directory), "skipped": found.skipped}
    (directory / MANIFEST).write_text(json.dumps(document, indent=1))
    return document
