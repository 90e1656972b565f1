"""The seam between storage formats and the reader: one protocol every format implements."""

from __future__ import annotations

import heapq
from collections.abc import Collection, Iterator, Mapping, Sequence
from dataclasses import replace
from typing import Protocol

from bagmcp_shared.bags.models import Compression, Connection, RawMessage

TopicTotals = Mapping[str, tuple[int, int | None, int | None]]  # topic -> (count, first ns, last ns) of a bag


class MessageSource(Protocol):
    """One storage file (or a whole ROS 1 bag) that yields raw messages by connection and time.

    ``messages`` yields in log-time order and uses the format's own index, so asking for one
    topic or a short window never reads the whole file when the file has an index.
    """

    @property
    def connections(self) -> Sequence[Connection]: ...

    @property
    def notes(self) -> Sequence[str]: ...

    @property
    def compression(self) -> Compression:
        """How the messages are compressed on disk (what most chunks use)."""
        ...

    def bounds(self, connection_id: int) -> tuple[int, int] | None:
        """Log times (ns) of the first and last message of a connection; None when empty."""
        ...

    def messages(
        self, connection_ids: Collection[int], *, start_ns: int | None, stop_ns: int | None
    ) -> Iterator[RawMessage]:
        """Messages of the given connections with ``start_ns <= t < stop_ns``, in time order."""
        ...

    def close(self) -> None: ...


class ListedSource:
    """The part of a ``MessageSource`` that lists what it found at open: its ``_connections`` (set by the
    subclass) and its ``_notes`` (none unless the subclass sets some)."""

    _connections: list[Connection]
    _notes: Sequence[str] = ()

    @property
    def connections(self) -> Sequence[Connection]:
        return self._connections

    @property
    def notes(self) -> Sequence[str]:
        return self._notes


class MergedSource(ListedSource):
    """Several storage files of one bag (split ROS 2 bags) seen as one source.

    Connections with the same topic and type across files become one connection whose count
    is the sum; messages from all files are merged in time order. The compression is ``compression``
    when given (a ROS 2 bag's compression_mode), else what most of its files use. ``totals``, when given,
    are each topic's count and first and last time in the whole bag, known beforehand (team mode: the
    catalog's, counted at ingest from these very files): they stand for the files' own, which then need not
    be counted (a sqlite3 file counts by a scan of every row); each topic must have one type.
    """

    def __init__(
        self,
        sources: Sequence[MessageSource],
        *,
        notes: Sequence[str] = (),
        compression: Compression | None = None,
        totals: TopicTotals | None = None,
    ) -> None:
        self._sources = list(sources)
        self._totals = totals
        self._notes = list(notes)
        self._compression = compression
        self._local_to_global: list[dict[int, Connection]] = []
        merged: dict[tuple[str, str], Connection] = {}
        for source in self._sources:
            mapping: dict[int, Connection] = {}
            for conn in source.connections:
                key = (conn.topic, conn.msgtype)
                known = merged.get(key)
                if known is None:
                    known = replace(conn, id=len(merged) + 1, count=0)
                merged[key] = replace(known, count=known.count + conn.count)
                mapping[conn.id] = merged[key]
            self._local_to_global.append(mapping)
        if totals is not None:
            merged = {key: replace(conn, count=totals[conn.topic][0]) for key, conn in merged.items()}
        self._connections = list(merged.values())
        for mapping in self._local_to_global:
            for local_id, conn in mapping.items():
                mapping[local_id] = merged[(conn.topic, conn.msgtype)]

    @property
    def notes(self) -> Sequence[str]:
        return [*self._notes, *(note for source in self._sources for note in source.notes)]

    @property
    def compression(self) -> Compression:
        if self._compression is None:
            self._compression = Compression.of_chunks(s.compression.value for s in self._sources)
        return self._compression

    def bounds(self, connection_id: int) -> tuple[int, int] | None:
        if self._totals is not None:
            topic = next(c.topic for c in self._connections if c.id == connection_id)
            _, first, last = self._totals[topic]
            return (first, last) if first is not None and last is not None else None
        found: list[tuple[int, int]] = []
        for source, mapping in zip(self._sources, self._local_to_global, strict=True):
            for local_id, conn in mapping.items():
                if conn.id == connection_id and (b := source.bounds(local_id)) is not None:
                    found.append(b)
        if not found:
            return None
        return min(b[0] for b in found), max(b[1] for b in found)

    def messages(
        self, connection_ids: Collection[int], *, start_ns: int | None, stop_ns: int | None
    ) -> Iterator[RawMessage]:
        wanted = set(connection_ids)
        streams = [
            self._relabel(source, mapping, wanted, start_ns, stop_ns)
            for source, mapping in zip(self._sources, self._local_to_global, strict=True)
        ]
        return heapq.merge(*streams, key=lambda m: m.log_time_ns)

    @staticmethod
    def _relabel(
        source: MessageSource,
        mapping: dict[int, Connection],
        wanted: set[int],
        start_ns: int | None,
        stop_ns: int | None,
    ) -> Iterator[RawMessage]:
        local_ids = [lid for lid, conn in mapping.items() if conn.id in wanted]
        if not local_ids:
            return
        for msg in source.messages(local_ids, start_ns=start_ns, stop_ns=stop_ns):
            yield RawMessage(mapping[msg.connection.id], msg.log_time_ns, msg.data)

    def close(self) -> None:
        for source in self._sources:
            source.close()
