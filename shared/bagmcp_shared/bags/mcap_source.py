"""MCAP files (bare or inside a ROS 2 bag directory), read with the ``mcap`` library.

With a summary section the file's chunk indexes serve topic and time queries. Without one
(a recording that was cut off) the file is streamed: if the data ends on a record boundary
everything is recovered and a note says so; if it ends inside a record the file is
truncated, which is an error unless the caller asked to recover what precedes the cut.
"""

from __future__ import annotations

import struct
from collections.abc import Collection, Iterator, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import BinaryIO

from mcap.exceptions import McapError
from mcap.reader import SeekingReader
from mcap.records import Channel, Chunk, Message, Schema
from mcap.stream_reader import StreamReader, breakup_chunk
from mcap.summary import Summary
from rosbags.typesys.msg import normalize_msgtype

from bagmcp_shared.bags.models import Connection, Encoding, RawMessage
from bagmcp_shared.errors import DamagedBagError, UnsupportedFormatError

_ENCODINGS = {"ros1": Encoding.ROS1, "cdr": Encoding.CDR}
_SCHEMA_FORMATS = {"ros1msg": "msg", "ros2msg": "msg", "ros2idl": "idl"}
_READ_ERRORS = (McapError, struct.error, ValueError, EOFError, RuntimeError)


def _msgtype(name: str) -> str:
    """ROS 1 profile schemas are named ``pkg/Type``; use the ``pkg/msg/Type`` form everywhere."""
    return normalize_msgtype(name) if name.count("/") == 1 else name


def _connection(channel: Channel, schema: Schema | None, count: int) -> Connection:
    return Connection(
        id=channel.id,
        topic=channel.topic,
        msgtype=_msgtype(schema.name) if schema else "",
        encoding=_ENCODINGS[channel.message_encoding],
        definition=schema.data.decode("utf-8", "replace") if schema else "",
        definition_format=_SCHEMA_FORMATS.get(schema.encoding, "") if schema else "",
        count=count,
        metadata=tuple(sorted(channel.metadata.items())),
    )


@dataclass
class _Scan:
    """What one streaming pass over the file learned."""

    schemas: dict[int, Schema] = field(default_factory=dict)
    channels: dict[int, Channel] = field(default_factory=dict)
    counts: dict[int, int] = field(default_factory=dict)
    bounds: dict[int, tuple[int, int]] = field(default_factory=dict)
    good_end: int = 0
    clean: bool = True
    error: str = ""

    def add(self, msg: Message) -> None:
        cid = msg.channel_id
        self.counts[cid] = self.counts.get(cid, 0) + 1
        lo, hi = self.bounds.get(cid, (msg.log_time, msg.log_time))
        self.bounds[cid] = (min(lo, msg.log_time), max(hi, msg.log_time))


def _stream_records(file: BinaryIO) -> Iterator[Schema | Channel | Message | int]:
    """Top-level records in file order; yields the byte offset after each complete record."""
    file.seek(0)
    for record in StreamReader(file, emit_chunks=True).records:
        end = file.tell()
        items = breakup_chunk(record) if isinstance(record, Chunk) else [record]
        for item in items:
            if isinstance(item, Schema | Channel | Message):
                yield item
        yield end


class McapSource:
    """One MCAP file."""

    def __init__(self, path: Path, *, recover_truncated: bool = False) -> None:
        self._path = path
        self._file: BinaryIO = path.open("rb")
        self._notes: list[str] = []
        try:
            reader = SeekingReader(self._file)
            self.profile = reader.get_header().profile
        except _READ_ERRORS as err:
            self._file.close()
            raise DamagedBagError(f"{path}: not a readable MCAP file ({err or type(err).__name__})") from err
        self._summary = self._read_summary(reader)
        self._reader = reader
        if self._summary is not None:
            self._connections, self._bounds = self._from_summary(self._summary)
        else:
            self._connections, self._bounds = self._from_scan(recover_truncated)

    def _read_summary(self, reader: SeekingReader) -> Summary | None:
        try:
            summary = reader.get_summary()
        except _READ_ERRORS:
            return None
        if summary is None or summary.statistics is None or not summary.chunk_indexes:
            return None
        return summary

    def _ros_channels(self, channels: dict[int, Channel]) -> list[Channel]:
        ros = [c for c in channels.values() if c.message_encoding in _ENCODINGS]
        other = sorted({c.message_encoding for c in channels.values()} - set(_ENCODINGS))
        if channels and not ros:
            raise UnsupportedFormatError(
                f"{self._path}: MCAP profile {self.profile!r} with message encoding "
                f"{', '.join(other)!s} is not a ROS recording (bagmcp reads ros1 and cdr)"
            )
        if other:
            self._notes.append(f"channels with non-ROS encodings ({', '.join(other)}) are skipped")
        return sorted(ros, key=lambda c: c.id)

    def _from_summary(self, summary: Summary) -> tuple[list[Connection], dict[int, tuple[int, int]]]:
        assert summary.statistics is not None
        counts = summary.statistics.channel_message_counts
        conns = [
            _connection(ch, summary.schemas.get(ch.schema_id), counts.get(ch.id, 0))
            for ch in self._ros_channels(summary.channels)
        ]
        return conns, {}

    def _from_scan(self, recover: bool) -> tuple[list[Connection], dict[int, tuple[int, int]]]:
        scan = self._scan()
        self._good_end = scan.good_end
        saved = sum(scan.counts.values())
        if not scan.clean and (not recover or not saved):
            rescue = (
                f"{saved} messages before the cut can be recovered on request"
                if saved
                else "nothing before the cut is complete enough to recover"
            )
            raise DamagedBagError(
                f"{self._path}: the MCAP file is truncated at byte {scan.good_end} of "
                f"{self._path.stat().st_size} ({scan.error}); {rescue}"
            )
        total = sum(scan.counts.values())
        if scan.clean:
            self._notes.append(
                f"the MCAP file has no summary or index (recording cut off?); all {total} "
                "messages were recovered by reading it from start to end"
            )
        else:
            self._notes.append(
                f"the MCAP file is truncated at byte {scan.good_end}; {total} messages before "
                "the cut were recovered, later ones are lost"
            )
        conns = [
            _connection(ch, scan.schemas.get(ch.schema_id), scan.counts.get(ch.id, 0))
            for ch in self._ros_channels(scan.channels)
        ]
        return conns, scan.bounds

    def _scan(self) -> _Scan:
        scan = _Scan()
        try:
            for item in _stream_records(self._file):
                if isinstance(item, int):
                    scan.good_end = item
                elif isinstance(item, Schema):
                    scan.schemas[item.id] = item
                elif isinstance(item, Channel):
                    scan.channels[item.id] = item
                else:
                    scan.add(item)
        except _READ_ERRORS as err:
            size = self._path.stat().st_size
            scan.clean = scan.good_end == size
            scan.error = str(err) or type(err).__name__
        return scan

    @property
    def connections(self) -> Sequence[Connection]:
        return self._connections

    @property
    def notes(self) -> Sequence[str]:
        return self._notes

    def bounds(self, connection_id: int) -> tuple[int, int] | None:
        if self._summary is None:
            return self._bounds.get(connection_id)
        if connection_id not in self._bounds:
            first = next(self._indexed([connection_id], None, None, reverse=False), None)
            last = next(self._indexed([connection_id], None, None, reverse=True), None)
            if first is None or last is None:
                return None
            self._bounds[connection_id] = (first.log_time_ns, last.log_time_ns)
        return self._bounds[connection_id]

    def messages(
        self, connection_ids: Collection[int], *, start_ns: int | None, stop_ns: int | None
    ) -> Iterator[RawMessage]:
        if self._summary is None:
            return self._streamed(connection_ids, start_ns, stop_ns)
        return self._indexed(connection_ids, start_ns, stop_ns, reverse=False)

    def _indexed(
        self, ids: Collection[int], start_ns: int | None, stop_ns: int | None, *, reverse: bool
    ) -> Iterator[RawMessage]:
        by_id = {c.id: c for c in self._connections if c.id in set(ids)}
        if not by_id:
            return
        topics = sorted({c.topic for c in by_id.values()})
        try:
            for _schema, channel, msg in self._reader.iter_messages(
                topics, starting_at=start_ns, ending_before=stop_ns, reverse=reverse
            ):
                if (conn := by_id.get(channel.id)) is not None:
                    yield RawMessage(conn, msg.log_time, msg.data)
        except _READ_ERRORS as err:
            raise DamagedBagError(f"{self._path}: a chunk could not be read ({err})") from err

    def _streamed(self, ids: Collection[int], start_ns: int | None, stop_ns: int | None) -> Iterator[RawMessage]:
        by_id = {c.id: c for c in self._connections if c.id in set(ids)}
        try:
            for item in _stream_records(self._file):
                if isinstance(item, int) and item >= self._good_end:
                    return
                if not isinstance(item, Message) or (conn := by_id.get(item.channel_id)) is None:
                    continue
                if (start_ns is None or item.log_time >= start_ns) and (stop_ns is None or item.log_time < stop_ns):
                    yield RawMessage(conn, item.log_time, item.data)
        except _READ_ERRORS:
            return  # the cut was reported when the file was opened

    def close(self) -> None:
        self._file.close()
