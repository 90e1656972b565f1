"""MCAP files (bare or inside a ROS 2 bag directory).

With a summary section the ``mcap`` library's chunk indexes serve topic and time queries (the summary
read with one read of its section: ``mcap_summary``).
Without one (a recording that was cut off) the file is read from start to end (see
``mcap_scan``): if the data ends on a record boundary everything is recovered and a note says
so; if it ends inside a record the file is cut short, which is an error naming the cut record
unless the caller asked to recover what precedes the cut (complete messages of a cut chunk too).
"""

from __future__ import annotations

import base64
import json
from collections.abc import Callable, Collection, Iterator
from dataclasses import replace
from pathlib import Path
from typing import BinaryIO, TypeVar

from mcap.records import Channel, Message, Schema
from mcap.summary import Summary
from rosbags.typesys.msg import normalize_msgtype

from bagmcp_shared.bags.json_types import infer_schema
from bagmcp_shared.bags.mcap_bounds import indexed_bounds
from bagmcp_shared.bags.mcap_chunk_budget import check_chunks
from bagmcp_shared.bags.mcap_cut_text import cut_error, cut_note
from bagmcp_shared.bags.mcap_lz4_bound import bound_library_lz4
from bagmcp_shared.bags.mcap_records import RecordError
from bagmcp_shared.bags.mcap_scan import scan, stream
from bagmcp_shared.bags.mcap_summary import READ_ERRORS as _READ_ERRORS
from bagmcp_shared.bags.mcap_summary import SummaryAtOnceReader
from bagmcp_shared.bags.models import Compression, Connection, Encoding, RawMessage
from bagmcp_shared.bags.plain_types import type_name
from bagmcp_shared.bags.source import ListedSource
from bagmcp_shared.errors import DamagedBagError, UnsupportedFormatError

_ENCODINGS = {
    "ros1": Encoding.ROS1,
    "cdr": Encoding.CDR,
    "json": Encoding.JSON,
    "protobuf": Encoding.PROTOBUF,
    "data_tamer": Encoding.DATA_TAMER,
}
_SCHEMA_FORMATS = {"ros1msg": "msg", "ros2msg": "msg", "ros2idl": "idl", "jsonschema": "jsonschema"}
_SCHEMA_FORMATS |= {"protobuf": "protobuf", "data_tamer": "data_tamer"}
_T = TypeVar("_T")
bound_library_lz4()  # before any MCAP is read: the library's lz4 chunks within the memory budget


def _msgtype(name: str) -> str:
    """ROS 1 profile schemas are named ``pkg/Type``; use the ``pkg/msg/Type`` form everywhere."""
    return normalize_msgtype(name) if name.count("/") == 1 else name


def _definition(encoding: Encoding, schema: Schema | None) -> str:
    """The schema as connection text (protobuf's binary descriptor set base64-encoded)."""
    if schema is None:
        return ""
    if encoding is Encoding.PROTOBUF:
        return base64.b64encode(schema.data).decode("ascii")
    return schema.data.decode("utf-8", "replace")


def _type(encoding: Encoding, channel: Channel, schema: Schema | None) -> str:
    """ROS type names as ROS writes them; other schemas named so message paths can use them."""
    if encoding.is_ros:
        return _msgtype(schema.name) if schema else ""
    return type_name(schema.name if schema and schema.name else channel.topic)


def _connection(channel: Channel, schema: Schema | None, count: int) -> Connection:
    encoding = _ENCODINGS[channel.message_encoding]
    return Connection(
        id=channel.id,
        topic=channel.topic,
        msgtype=_type(encoding, channel, schema),
        encoding=encoding,
        definition=_definition(encoding, schema),
        definition_format=_SCHEMA_FORMATS.get(schema.encoding, "") if schema else "",
        count=count,
        metadata=tuple(sorted(channel.metadata.items())),
    )


class McapSource(ListedSource):
    """One MCAP file: a local ``path``, or a seekable ``stream`` of ``size`` bytes named ``path``."""

    def __init__(
        self, path: Path, *, recover_truncated: bool = False, stream: BinaryIO | None = None, size: int = 0
    ) -> None:
        self._path = path
        self._file: BinaryIO = stream if stream is not None else path.open("rb")
        self._size = size if stream is not None else 0
        self._notes: list[str] = []
        try:
            self._open(recover_truncated)
        except BaseException:  # refused (damaged, an encoding not decoded, over budget): the file is not left open
            self._file.close()
            raise

    def _open(self, recover_truncated: bool) -> None:
        try:
            reader = SummaryAtOnceReader(self._file)
            self.profile = reader.get_header().profile
        except _READ_ERRORS as err:
            raise DamagedBagError(f"{self._path}: not a readable MCAP file ({err or type(err).__name__})") from err
        self._summary = self._read_summary(reader)
        self._reader = reader
        if (summary := self._summary) is not None:
            hint = getattr(self._file, "hint_records", None)
            # A ranged file (team mode) is an object ingest already read whole and checked, pinned by its ETag:
            # its chunk records are not fetched again just to check their heads, only the index's sizes.
            self._checked(lambda: check_chunks(self._file, summary.chunk_indexes, read_records=hint is None))
            if hint is not None:
                hint([(c.chunk_start_offset, c.chunk_start_offset + c.chunk_length) for c in summary.chunk_indexes])
            self._connections, self._bounds = self._from_summary(summary)
            chunks = [index.compression for index in summary.chunk_indexes]
        else:
            self._connections, self._bounds, chunks = self._from_scan(recover_truncated)
        self._compression = Compression.of_chunks(chunks)
        self._connections = self._with_inferred_schemas(self._connections)

    def _checked(self, work: Callable[[], _T]) -> _T:
        """``work()``, whose budget refusal is named with the file."""
        try:
            return work()
        except UnsupportedFormatError as err:
            raise UnsupportedFormatError(f"{self._path}: {err}") from err

    def _read_summary(self, reader: SummaryAtOnceReader) -> Summary | None:
        try:
            summary = reader.get_summary()
        except _READ_ERRORS:
            return None
        if summary is None or summary.statistics is None or not summary.chunk_indexes:
            return None
        return summary

    def _readable_channels(self, channels: dict[int, Channel]) -> list[Channel]:
        known = [c for c in channels.values() if c.message_encoding in _ENCODINGS]
        other = sorted({c.message_encoding for c in channels.values()} - set(_ENCODINGS))
        readable = ", ".join(_ENCODINGS)
        if channels and not known:
            raise UnsupportedFormatError(
                f"{self._path}: MCAP profile {self.profile!r} with message encoding "
                f"{', '.join(other)!s} cannot be decoded (bagmcp reads {readable})"
            )
        if other:
            self._notes.append(f"channels with encodings bagmcp cannot decode ({', '.join(other)}) are skipped")
        return sorted(known, key=lambda c: c.id)

    def _with_inferred_schemas(self, connections: list[Connection]) -> list[Connection]:
        """JSON channels without a schema get one inferred from their first message."""
        found = []
        for conn in connections:
            if conn.encoding is Encoding.JSON and not conn.definition and conn.count:
                first = next(self.messages([conn.id], start_ns=None, stop_ns=None), None)
                try:
                    sample = json.loads(first.data) if first is not None else {}
                except ValueError:
                    sample = {}
                conn = replace(conn, definition=json.dumps(infer_schema(sample)), definition_format="jsonschema")
                self._notes.append(f"{conn.topic}: JSON without a schema; its fields were taken from its first message")
            found.append(conn)
        return found

    def _from_summary(self, summary: Summary) -> tuple[list[Connection], dict[int, tuple[int, int]]]:
        assert summary.statistics is not None
        counts = summary.statistics.channel_message_counts
        conns = [
            _connection(ch, summary.schemas.get(ch.schema_id), counts.get(ch.id, 0))
            for ch in self._readable_channels(summary.channels)
        ]
        return conns, {}

    def _from_scan(self, recover: bool) -> tuple[list[Connection], dict[int, tuple[int, int]], list[str]]:
        found = self._checked(lambda: scan(self._file, self._file_size()))
        cut = found.cut
        if cut is None:
            self._notes.append(
                f"the MCAP file has no summary or index (recording cut off?); all {found.total} "
                "messages were recovered by reading it from start to end"
            )
        elif cut.after_data or (recover and found.total):
            self._notes.append(cut_note(cut, found.channels))
        else:
            raise DamagedBagError(f"{self._path}: {cut_error(cut, found.channels)}")
        conns = [
            _connection(ch, found.schemas.get(ch.schema_id), found.counts.get(ch.id, 0))
            for ch in self._readable_channels(found.channels)
        ]
        return conns, found.bounds, found.chunk_compressions

    @property
    def compression(self) -> Compression:
        """What most chunks use (zstd, lz4 or none)."""
        return self._compression

    def bounds(self, connection_id: int) -> tuple[int, int] | None:
        if self._summary is None:
            return self._bounds.get(connection_id)
        if connection_id not in self._bounds and (
            found := indexed_bounds(self._file, self._summary.chunk_indexes, connection_id)
        ):
            self._bounds[connection_id] = found
        if connection_id not in self._bounds:  # no message index to read: the first and last messages
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
        except UnsupportedFormatError as err:  # a chunk past the memory budget (mcap_lz4_bound)
            raise UnsupportedFormatError(f"{self._path}: {err}") from err

    def _streamed(self, ids: Collection[int], start_ns: int | None, stop_ns: int | None) -> Iterator[RawMessage]:
        by_id = {c.id: c for c in self._connections if c.id in set(ids)}
        try:
            for item in stream(self._file, self._file_size()):
                if not isinstance(item, Message) or (conn := by_id.get(item.channel_id)) is None:
                    continue
                if (start_ns is None or item.log_time >= start_ns) and (stop_ns is None or item.log_time < stop_ns):
                    yield RawMessage(conn, item.log_time, item.data)
        except RecordError:
            return  # the damage was reported (or accepted for recovery) when the file was opened

    def _file_size(self) -> int:
        return self._size or self._path.stat().st_size

    def close(self) -> None:
        self._file.close()
