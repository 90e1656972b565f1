"""An MCAP file's summary section read with one read of the stream and parsed from memory.

The ``mcap`` library's ``SeekingReader.get_summary`` parses the summary straight off the stream, record by
record: every field is its own small ``read()``. On a ``RangedFile`` (team mode) each of those goes through
Python-level block look-ups, and any part of the summary past the prefetched end is fetched as it is
reached: on a 2 GB bag that was 150 ms of a 262 ms cold point read (issue 21). Here the footer says where
the summary starts; the whole section (with the footer after it) is read at once and the same records are
parsed from memory (chunk indexes with struct, the others by the library's record classes), collected into a
``Summary`` as the library collects them.

Whenever the quick way cannot tell what the library would do (the footer unreadable or inconsistent, the
section past ``SUMMARY_AT_ONCE_MAX_BYTES``, the bytes failing to parse), the library's own ``get_summary``
runs, so a damaged file gives exactly the errors or results it gave before.
"""

from __future__ import annotations

import io
import struct
from collections.abc import Iterator
from typing import IO, Literal

from mcap.data_stream import ReadDataStream
from mcap.exceptions import McapError
from mcap.opcode import Opcode
from mcap.reader import SeekingReader
from mcap.records import (
    Attachment,
    AttachmentIndex,
    Channel,
    ChunkIndex,
    DataEnd,
    Footer,
    Header,
    McapRecord,
    Message,
    MessageIndex,
    Metadata,
    MetadataIndex,
    Schema,
    Statistics,
    SummaryOffset,
)
from mcap.summary import Summary

from bagmcp_shared.bags.mcap_records import MAGIC_BYTES

# A summary is small beside its bag: a chunk index is ~150 bytes with 8 channels (a file shaped like the 2 GB
# bench bag, 2,000 chunks of 1 MiB, has a 307 KB summary), so 64 MiB holds some 400,000 chunk indexes, hundreds
# of GB of recording. A footer may claim any start: a section past this is not loaded at once (the library
# reads it record by record, as before), so a hostile footer cannot make one allocation of gigabytes.
SUMMARY_AT_ONCE_MAX_BYTES = 64 << 20
_FOOTER = struct.Struct("<BQQQI")  # opcode, content length, summary start, summary offset start, summary CRC
_FOOTER_CONTENT_BYTES = _FOOTER.size - 9  # after the opcode and the length
_RECORD_HEAD = struct.Struct("<BQ")  # opcode, content length
_CHUNK_INDEX_HEAD = struct.Struct("<QQQQI")  # start and end times, chunk offset and length, offsets' bytes
_OFFSET = struct.Struct("<HQ")  # channel id, message index offset
# Every other record the library knows, parsed by its own record class (a record the summary does not keep is
# still parsed, so bytes the library refused are refused here too); a message's read also takes its length. A
# chunk, which the spec keeps out of the summary, is left to the library (it would read the records inside).
_LIBRARY: dict[int, type[McapRecord]] = {
    Opcode.ATTACHMENT: Attachment,
    Opcode.ATTACHMENT_INDEX: AttachmentIndex,
    Opcode.CHANNEL: Channel,
    Opcode.DATA_END: DataEnd,
    Opcode.FOOTER: Footer,
    Opcode.HEADER: Header,
    Opcode.MESSAGE_INDEX: MessageIndex,
    Opcode.METADATA: Metadata,
    Opcode.METADATA_INDEX: MetadataIndex,
    Opcode.SCHEMA: Schema,
    Opcode.STATISTICS: Statistics,
    Opcode.SUMMARY_OFFSET: SummaryOffset,
}
# What the mcap library raises on bytes it cannot parse (McapSource reports them as damage).
READ_ERRORS = (McapError, struct.error, ValueError, EOFError, RuntimeError)


class _NotAtOnceError(Exception):
    """The summary cannot be read in one go here; the library's record-by-record read decides."""


def _section_span(stream: IO[bytes]) -> tuple[int, int] | None:
    """(summary start, footer end) from the footer; None when the footer says there is no summary."""
    end = stream.seek(0, io.SEEK_END)
    footer_at = end - MAGIC_BYTES - _FOOTER.size
    if footer_at < MAGIC_BYTES:
        raise _NotAtOnceError
    stream.seek(footer_at)
    raw = stream.read(_FOOTER.size)
    if len(raw) != _FOOTER.size:
        raise _NotAtOnceError
    opcode, length, summary_start, _offsets, _crc = _FOOTER.unpack(raw)
    if opcode != Opcode.FOOTER or length != _FOOTER_CONTENT_BYTES:
        raise _NotAtOnceError
    if summary_start == 0:
        return None
    if summary_start > footer_at or footer_at - summary_start > SUMMARY_AT_ONCE_MAX_BYTES:
        raise _NotAtOnceError
    return summary_start, footer_at + _FOOTER.size


def _collected(section: bytes, record_size_limit: int | None) -> Summary | None:
    """The summary records of ``section`` (the summary section and the footer after it), as the library
    collects them: the last statistics record, schemas and channels by id, the indexes in file order, up to
    the first footer (one whose summary start is 0 means no summary). Each record is parsed within its own
    length; chunk indexes, nearly all of a summary, with struct (``_chunk_index``)."""
    summary = Summary()
    for opcode, content in _records(section, record_size_limit):
        if opcode == Opcode.CHUNK_INDEX:
            summary.chunk_indexes.append(_chunk_index(content))
            continue
        if opcode == Opcode.CHUNK:
            raise _NotAtOnceError
        record = _library_record(opcode, content)
        if isinstance(record, Statistics):
            summary.statistics = record
        elif isinstance(record, Schema):
            summary.schemas[record.id] = record
        elif isinstance(record, Channel):
            summary.channels[record.id] = record
        elif isinstance(record, AttachmentIndex):
            summary.attachment_indexes.append(record)
        elif isinstance(record, MetadataIndex):
            summary.metadata_indexes.append(record)
        elif isinstance(record, Footer):
            return summary if record.summary_start else None
    raise _NotAtOnceError  # a section without a footer: the library decides


def _records(section: bytes, record_size_limit: int | None) -> Iterator[tuple[int, bytes]]:
    """(opcode, content) of each record of ``section``; a record past the limit or the section's end is not
    parsed here (``_NotAtOnceError``: the library decides, raising what it raised before)."""
    pos = 0
    while pos + _RECORD_HEAD.size <= len(section):
        opcode, length = _RECORD_HEAD.unpack_from(section, pos)
        pos += _RECORD_HEAD.size
        if (record_size_limit is not None and length > record_size_limit) or pos + length > len(section):
            raise _NotAtOnceError
        yield opcode, section[pos : pos + length]
        pos += length


def _library_record(opcode: int, content: bytes) -> McapRecord | None:
    """The record as the library's reader parses it; None for an opcode it does not know (it skips those)."""
    stream = ReadDataStream(io.BytesIO(content))
    if opcode == Opcode.MESSAGE:
        message: Message = Message.read(stream, len(content))
        return message
    kind = _LIBRARY.get(opcode)
    return None if kind is None else kind.read(stream)  # type: ignore[attr-defined]


def _chunk_index(content: bytes) -> ChunkIndex:
    """A chunk index record parsed with struct, field by field as the library's ``ChunkIndex.read`` reads it:
    the 2 GB bench bag's summary (1,001 chunk indexes, 130 KB) took 7.4 ms to parse with the library's reader
    (every field a small read of a BytesIO) and 2.5 ms so (best of 20, in process). Raises struct.error or
    ValueError for bytes that do not parse."""
    start, end, offset, length, map_bytes = _CHUNK_INDEX_HEAD.unpack_from(content)
    if map_bytes % _OFFSET.size:
        raise ValueError("a chunk index's message index offsets are not whole entries")
    at = _CHUNK_INDEX_HEAD.size
    offsets = dict(_OFFSET.iter_unpack(content[at : at + map_bytes]))
    at += map_bytes
    index_length, name_bytes = struct.unpack_from("<QI", content, at)
    at += 12
    compression = content[at : at + name_bytes].decode()
    compressed, uncompressed = struct.unpack_from("<QQ", content, at + name_bytes)  # past the end: struct.error
    return ChunkIndex(
        message_start_time=start,
        message_end_time=end,
        chunk_start_offset=offset,
        chunk_length=length,
        message_index_offsets=offsets,
        message_index_length=index_length,
        compression=compression,
        compressed_size=compressed,
        uncompressed_size=uncompressed,
    )


def summary_at_once(stream: IO[bytes], record_size_limit: int | None) -> Summary | None:
    """The summary of the MCAP file ``stream`` read with one read of its summary section (None when its
    footer says it has none). Raises ``_NotAtOnceError`` when the library's own read must decide; errors of the
    stream itself (a storage outage, a changed object) are raised as the library's reads raise them."""
    span = _section_span(stream)
    if span is None:
        return None
    start, stop = span
    stream.seek(start)
    section = stream.read(stop - start)
    if len(section) != stop - start:
        raise _NotAtOnceError
    try:
        return _collected(section, record_size_limit)
    except READ_ERRORS as err:
        raise _NotAtOnceError from err


class SummaryAtOnceReader(SeekingReader):
    """A ``SeekingReader`` whose summary is read with one read of the stream (``summary_at_once``).

    A subclass overriding ``get_summary``, not the library's reader with its private ``_summary`` set from
    outside: ``iter_messages`` and the other methods find the summary through ``get_summary``, so overriding
    that public method puts every caller on this summary, and a library release that renames or drops its
    private cache breaks nothing here. When the summary cannot be read at once, the library's
    ``get_summary`` runs (and raises or returns what it always did)."""

    def __init__(self, stream: IO[bytes], *, record_size_limit: int | None = 4 << 30) -> None:
        super().__init__(stream, record_size_limit=record_size_limit)
        self._source = stream
        self._limit = record_size_limit
        self._how: Literal["unread", "at once", "library"] = "unread"
        self._at_once: Summary | None = None

    def get_summary(self) -> Summary | None:
        if self._how == "unread":  # stays unread when the stream failed (an outage): the next call reads again
            try:
                self._at_once, self._how = summary_at_once(self._source, self._limit), "at once"
            except _NotAtOnceError:
                self._how = "library"
        return super().get_summary() if self._how == "library" else self._at_once
