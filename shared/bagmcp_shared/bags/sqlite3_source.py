"""ROS 2 sqlite3 storage files (``.db3``): a local file read with the standard library's sqlite3, a stored
one through a stream with apsw (see sqlite3_stream.py); the same queries either way.

The storage file is the truth: topics, counts and definitions come from its tables, not from
``metadata.yaml`` (which real bags sometimes contradict).
"""

from __future__ import annotations

import sqlite3
import threading
from collections import OrderedDict
from collections.abc import Collection, Iterable, Iterator, Sequence
from contextlib import suppress
from dataclasses import replace
from pathlib import Path
from typing import Any, BinaryIO, Protocol

import apsw

from bagmcp_shared.bags.models import Compression, Connection, Encoding, RawMessage
from bagmcp_shared.bags.source import ListedSource
from bagmcp_shared.bags.sqlite3_stream import connect_stream
from bagmcp_shared.errors import DamagedBagError, UnsupportedFormatError

_DEFINITION_FORMATS = {"ros2msg": "msg", "ros2idl": "idl"}
_DB_ERRORS = (sqlite3.Error, apsw.Error)


class Database(Protocol):
    """What is used of a connection: sqlite3's and apsw's both have it."""

    def execute(self, sql: str, params: Sequence[Any] = ..., /) -> Iterable[Any]: ...

    def close(self) -> None: ...


def _checked(path: Path, db: Database) -> Database:
    """``db`` once it reads as a database with its two tables; closed and a DamagedBagError naming ``path`` when
    it does not. ``LIMIT 0`` prepares each query against the schema without reading a row: ``LIMIT 1`` on
    messages walked a b-tree (the table's or its timestamp index's) down to the first row: two pages far apart
    in a large file, which read by range were two more round trips to the object store in every cold open (in
    the benchmark's 2 GB .db3, blocks 1,799 and 10 after block 0). A damaged table is still found, by the first
    read of its rows."""
    try:
        list(db.execute("SELECT 1 FROM messages LIMIT 0"))
        list(db.execute("SELECT 1 FROM topics LIMIT 0"))
    except _DB_ERRORS as err:
        db.close()
        raise DamagedBagError(f"{path}: not a readable ROS 2 sqlite3 bag ({err})") from err
    return db


def _local_uri(path: Path) -> str:
    """Read-only and, unless a write-ahead log holds pages not yet in the file, immutable: SQLite then
    takes no locks and creates no ``-wal``/``-shm`` files beside a WAL-mode bag (``mode=ro`` alone creates
    both, writing into a folder the server serves and promises never to write to). A non-empty ``-wal``
    (a recording that was not checkpointed) holds messages the file lacks, so it is read through SQLite's
    WAL machinery, which needs the ``-shm`` index beside it."""
    wal = path.with_name(path.name + "-wal")
    pending = wal.exists() and wal.stat().st_size > 0
    return f"{path.resolve().as_uri()}?mode=ro" + ("" if pending else "&immutable=1")


def _connect(path: Path, stream: tuple[BinaryIO, int] | None) -> Database:
    """The local file at ``path`` (sqlite3, see ``_local_uri``), or the database in ``stream`` (apsw, always
    immutable: a stored bag has no side files)."""
    try:
        if stream is not None:
            return _checked(path, connect_stream(*stream))
        return _checked(path, sqlite3.connect(_local_uri(path), uri=True, check_same_thread=False))
    except _DB_ERRORS as err:
        raise DamagedBagError(f"{path}: not a readable ROS 2 sqlite3 bag ({err})") from err


def _columns(db: Database, table: str) -> set[str]:
    return {str(row[1]) for row in db.execute(f"PRAGMA table_info({table})")}


def _definitions(db: Database) -> dict[str, tuple[str, str]]:
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


def file_key(path: Path) -> tuple[object, ...]:
    """Identity of a storage file's content: path, size and mtime, with its WAL file if any."""
    parts: list[object] = [str(path.resolve())]
    for member in (path, path.with_name(path.name + "-wal")):
        with suppress(FileNotFoundError):
            info = member.stat()
            parts += [info.st_size, info.st_mtime_ns]
    return tuple(parts)


def _stream_key(stream: BinaryIO) -> tuple[object, ...] | None:
    """Identity of a stream's content when the stream tells it (``RangedFile.identity``: the object and
    its ETag), else None (then nothing is remembered)."""
    identity = getattr(stream, "identity", None)
    return ("stream", identity) if isinstance(identity, str) and identity else None


def topic_stats(db: Database, key: tuple[object, ...] | None) -> TopicStats:
    """Per-topic count and first/last timestamps. The table has no topic index, so this scans every
    row (every page of the file): done once per file content (``key``) and process, not on every open."""
    with _STATS_LOCK:
        if key is not None and (known := _STATS.get(key)) is not None:
            _STATS.move_to_end(key)
            return known
    stats = {
        int(tid): (int(n), int(lo), int(hi))
        for tid, n, lo, hi in db.execute(
            "SELECT topic_id, COUNT(*), MIN(timestamp), MAX(timestamp) FROM messages GROUP BY topic_id"
        )
    }
    with _STATS_LOCK:
        if key is not None:
            _STATS[key] = stats
        while len(_STATS) > _STATS_KEPT:
            _STATS.popitem(last=False)
    return stats


def forget_topic_stats() -> None:
    """Forget every remembered count, as a fresh process would (tests of what an open fetches use it)."""
    with _STATS_LOCK:
        _STATS.clear()


class Sqlite3Source(ListedSource):
    """One ``.db3`` file: a local one at ``path``, or one read through ``stream`` (a seekable stream and its
    size; ``path`` then names it in messages). Opened with ``counted=False`` it does not count each topic's
    messages, a scan of every row that on a stored file fetches all of it: its connections then hold no
    count and it knows no bounds, until ``count_rows`` (whoever opens it so has the counts from elsewhere:
    team mode from the catalog, see ``MergedSource``'s totals)."""

    def __init__(self, path: Path, *, stream: tuple[BinaryIO, int] | None = None, counted: bool = True) -> None:
        self._path = path
        self._db = _connect(path, stream)
        self._key = file_key(path) if stream is None else _stream_key(stream[0])
        self._bounds: dict[int, tuple[int, int]] = {}
        try:
            self._connections = self._read_topics()
            if counted:
                self.count_rows()
        except _DB_ERRORS as err:
            self._db.close()
            raise DamagedBagError(f"{path}: the sqlite3 tables could not be read ({err})") from err
        except BaseException:
            self._db.close()
            raise

    def _read_topics(self) -> list[Connection]:
        db = self._db
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
            meta = (("offered_qos_profiles", str(qos)),) if qos else ()
            connections.append(Connection(int(tid), str(name), str(typ), Encoding.CDR, text, dfmt, 0, "", meta))
        return connections

    def count_rows(self) -> None:
        """Count each topic's messages and find its first and last time (see ``topic_stats``)."""
        try:
            stats = topic_stats(self._db, self._key)
        except _DB_ERRORS as err:
            raise DamagedBagError(f"{self._path}: the sqlite3 tables could not be read ({err})") from err
        self._connections = [replace(c, count=stats.get(c.id, (0, 0, 0))[0]) for c in self._connections]
        self._bounds = {tid: (lo, hi) for tid, (_, lo, hi) in stats.items()}

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
        except _DB_ERRORS as err:
            raise DamagedBagError(f"{self._path}: messages could not be read ({err})") from err

    def close(self) -> None:
        self._db.close()
