"""ROS 2 sqlite3 storage files (``.db3``), read with the standard library's sqlite3.

The storage file is the truth: topics, counts and definitions come from its tables, not from
``metadata.yaml`` (which real bags sometimes contradict).
"""

from __future__ import annotations

import sqlite3
import threading
from collections import OrderedDict
from collections.abc import Collection, Iterator, Sequence
from contextlib import suppress
from pathlib import Path

from bagmcp_shared.bags.models import Compression, Connection, Encoding, RawMessage
from bagmcp_shared.errors import DamagedBagError, UnsupportedFormatError

_DEFINITION_FORMATS = {"ros2msg": "msg", "ros2idl": "idl"}


def _connect(path: Path) -> sqlite3.Connection:
    """Open read-only and, unless a write-ahead log holds pages not yet in the file, immutable: SQLite then
    takes no locks and creates no ``-wal``/``-shm`` files beside a WAL-mode bag (``mode=ro`` alone creates
    both, writing into a folder the server serves and promises never to write to). A non-empty ``-wal``
    (a recording that was not checkpointed) holds messages the file lacks, so it is read through SQLite's
    WAL machinery, which needs the ``-shm`` index beside it."""
    wal = path.with_name(path.name + "-wal")
    pending = wal.exists() and wal.stat().st_size > 0
    uri = f"{path.resolve().as_uri()}?mode=ro" + ("" if pending else "&immutable=1")
    try:
        db = sqlite3.connect(uri, uri=True, check_same_thread=False)
        db.execute("SELECT 1 FROM messages LIMIT 1").fetchall()
        db.execute("SELECT 1 FROM topics LIMIT 1").fetchall()
    except sqlite3.Error as err:
        raise DamagedBagError(f"{path}: not a readable ROS 2 sqlite3 bag ({err})") from err
    return db


def _columns(db: sqlite3.Connection, table: str) -> set[str]:
    return {str(row[1]) for row in db.execute(f"PRAGMA table_info({table})")}


def _definitions(db: sqlite3.Connection) -> dict[str, tuple[str, str]]:
    if "topic_type" not in _columns(db, "message_definitions"):
        return {}
    rows = db.execute("SELECT topic_type, encoding, encoded_message_definition FROM message_definitions")
    return {
        str(typ): (str(text), _DEFINITION_FORMATS.get(str(enc), ""))
        for typ, enc, text in rows
        if str(text).strip() and str(enc) in _DEFINITION_FORMATS
    }


TopicStats = dict[int, tuple[int, int, int]]  # topic id -> (count, first ns, last ns)
_STATS: OrderedDict[tuple[object, ...], TopicStats] = OrderedDict()
_STATS_LOCK = threading.Lock()
_STATS_KEPT = 64


def _file_key(path: Path) -> tuple[object, ...]:
    """Identity of a storage file's content: path, size and mtime, with its WAL file if any."""
    parts: list[object] = [str(path.resolve())]
    for member in (path, path.with_name(path.name + "-wal")):
        with suppress(FileNotFoundError):
            info = member.stat()
            parts += [info.st_size, info.st_mtime_ns]
    return tuple(parts)


def topic_stats(db: sqlite3.Connection, path: Path) -> TopicStats:
    """Per-topic count and first/last timestamps. The table has no topic index, so this scans every
    row: done once per file content and process, not on every open."""
    key = _file_key(path)
    with _STATS_LOCK:
        if (known := _STATS.get(key)) is not None:
            _STATS.move_to_end(key)
            return known
    stats = {
        int(tid): (int(n), int(lo), int(hi))
        for tid, n, lo, hi in db.execute(
            "SELECT topic_id, COUNT(*), MIN(timestamp), MAX(timestamp) FROM messages GROUP BY topic_id"
        )
    }
    with _STATS_LOCK:
        _STATS[key] = stats
        while len(_STATS) > _STATS_KEPT:
            _STATS.popitem(last=False)
    return stats


class Sqlite3Source:
    """One ``.db3`` file."""

    def __init__(self, path: Path) -> None:
        self._path = path
        self._db = _connect(path)
        try:
            self._connections, self._bounds = self._read_topics()
        except sqlite3.Error as err:
            self._db.close()
            raise DamagedBagError(f"{path}: the sqlite3 tables could not be read ({err})") from err

    def _read_topics(self) -> tuple[list[Connection], dict[int, tuple[int, int]]]:
        db = self._db
        stats = topic_stats(db, self._path)
        has_qos = "offered_qos_profiles" in _columns(db, "topics")
        qos_col = "offered_qos_profiles" if has_qos else "''"
        defs = _definitions(db)
        connections: list[Connection] = []
        for tid, name, typ, fmt, qos in db.execute(
            f"SELECT id, name, type, serialization_format, {qos_col} FROM topics ORDER BY id"
        ):
            if str(fmt) != "cdr":
                raise UnsupportedFormatError(
                    f"{self._path}: topic {name} uses serialization format {fmt!r}; only 'cdr' can be read"
                )
            text, dfmt = defs.get(str(typ), ("", ""))
            count = stats.get(int(tid), (0, 0, 0))[0]
            meta = (("offered_qos_profiles", str(qos)),) if qos else ()
            connections.append(Connection(int(tid), str(name), str(typ), Encoding.CDR, text, dfmt, count, "", meta))
        bounds = {tid: (lo, hi) for tid, (_, lo, hi) in stats.items()}
        return connections, bounds

    @property
    def connections(self) -> Sequence[Connection]:
        return self._connections

    @property
    def notes(self) -> Sequence[str]:
        return []

    @property
    def compression(self) -> Compression:
        """A storage file holds plain rows; compression_mode in metadata.yaml is the bag's."""
        return Compression.NONE

    def bounds(self, connection_id: int) -> tuple[int, int] | None:
        return self._bounds.get(connection_id)

    def messages(
        self, connection_ids: Collection[int], *, start_ns: int | None, stop_ns: int | None
    ) -> Iterator[RawMessage]:
        by_id = {c.id: c for c in self._connections if c.id in set(connection_ids)}
        if not by_id:
            return
        marks = ",".join("?" for _ in by_id)
        query = f"SELECT topic_id, timestamp, data FROM messages WHERE topic_id IN ({marks})"
        args: list[int] = list(by_id)
        if start_ns is not None:
            query += " AND timestamp >= ?"
            args.append(start_ns)
        if stop_ns is not None:
            query += " AND timestamp < ?"
            args.append(stop_ns)
        query += " ORDER BY timestamp, id"
        try:
            for tid, timestamp, data in self._db.execute(query, args):
                yield RawMessage(by_id[int(tid)], int(timestamp), bytes(data))
        except sqlite3.Error as err:
            raise DamagedBagError(f"{self._path}: messages could not be read ({err})") from err

    def close(self) -> None:
        self._db.close()
