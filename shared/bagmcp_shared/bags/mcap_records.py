"""MCAP records read by hand, for files read from start to end (no summary, or cut short).

Every read is bounded by the bytes that are there, so a file cut short or full of garbage ends
in a :class:`RecordError` (a sentence fragment the caller completes), never a hang or a huge
allocation. A chunk cut short still gives the records that a streaming decompressor can
rebuild from the compressed bytes that are present.
"""

from __future__ import annotations

import io
import struct
from collections.abc import Iterator
from dataclasses import dataclass
from typing import BinaryIO

import lz4.frame  # type: ignore[import-untyped]
import zstandard
from mcap.opcode import Opcode
from mcap.records import Channel, Message, Schema

MAGIC_BYTES = 8
HEAD_BYTES = 9  # opcode (1) and content length (8) before every record
_READ_STEP_BYTES = 1 << 20
# Records a pass from start to end does not need, of any size: only their first bytes (which name them) are
# read, so an attachment of gigabytes is skipped instead of loaded.
_NOT_LOADED = frozenset({Opcode.ATTACHMENT, Opcode.METADATA})
_PREFIX_BYTES = 4096
_KINDS: dict[int, str] = {
    Opcode.HEADER: "header",
    Opcode.FOOTER: "footer",
    Opcode.SCHEMA: "schema",
    Opcode.CHANNEL: "channel",
    Opcode.MESSAGE: "message",
    Opcode.CHUNK: "chunk",
    Opcode.MESSAGE_INDEX: "message index",
    Opcode.CHUNK_INDEX: "chunk index",
    Opcode.ATTACHMENT: "attachment",
    Opcode.ATTACHMENT_INDEX: "attachment index",
    Opcode.STATISTICS: "statistics record",
    Opcode.METADATA: "metadata record",
    Opcode.METADATA_INDEX: "metadata index",
    Opcode.SUMMARY_OFFSET: "summary offset",
    Opcode.DATA_END: "data end record",
}


class RecordError(ValueError):
    """A record that cannot be parsed; ``str(err)`` completes "the record that starts at byte N"."""


def kind_of(opcode: int | None) -> str:
    if opcode is None:
        return "record"
    return _KINDS.get(opcode, f"record with opcode 0x{opcode:02x}")


@dataclass(frozen=True)
class Piece:
    """One top-level record as the file holds it; ``body`` is shorter than claimed when it is cut, and holds
    only the first bytes of an attachment or metadata record (``present_bytes`` says how many are there)."""

    offset: int
    opcode: int | None  # None when the file ends before the opcode byte
    claimed_bytes: int | None  # the content length its head states; None when the head is cut
    body: bytes
    present_bytes: int | None = None  # None: all of ``body``

    @property
    def complete(self) -> bool:
        present = len(self.body) if self.present_bytes is None else self.present_bytes
        return self.claimed_bytes is not None and present == self.claimed_bytes

    @property
    def kind(self) -> str:
        return kind_of(self.opcode)


def pieces(file: BinaryIO, size_bytes: int) -> Iterator[Piece]:
    """Top-level records after the magic, in file order, up to the footer or the end of the file.

    The last piece is incomplete when the file ends inside it; nothing is read past the file end.
    """
    offset = MAGIC_BYTES
    file.seek(offset)
    while offset < size_bytes:
        head = file.read(HEAD_BYTES)
        if len(head) < HEAD_BYTES:
            yield Piece(offset, head[0] if head else None, None, b"")
            return
        opcode, length = struct.unpack("<BQ", head)
        present = min(length, size_bytes - offset - HEAD_BYTES)
        if opcode in _NOT_LOADED:
            piece = Piece(offset, opcode, length, file.read(min(present, _PREFIX_BYTES)), present)
            file.seek(offset + HEAD_BYTES + present)
        else:
            piece = Piece(offset, opcode, length, file.read(present))
        yield piece
        if not piece.complete or opcode == Opcode.FOOTER:
            return
        offset += HEAD_BYTES + length


class Cursor:
    """Little-endian fields read from bytes; reading past the end raises :class:`RecordError`."""

    def __init__(self, data: bytes) -> None:
        self.data = data
        self.at = 0

    def take(self, count: int) -> bytes:
        if count > len(self.data) - self.at:
            raise RecordError(f"states a field of {count:,} bytes where only {len(self.data) - self.at:,} remain")
        self.at += count
        return self.data[self.at - count : self.at]

    def uint(self, width: int) -> int:
        return int.from_bytes(self.take(width), "little")

    def text(self) -> str:
        return self.take(self.uint(4)).decode("utf-8", "replace")

    def rest(self) -> bytes:
        return self.take(len(self.data) - self.at)


@dataclass(frozen=True)
class ChunkHead:
    """A chunk's fields; ``data`` holds the compressed records present (all of them when whole)."""

    start_ns: int
    end_ns: int
    uncompressed_bytes: int
    compression: str
    data: bytes


def chunk_head(body: bytes, *, whole: bool) -> ChunkHead:
    fields = Cursor(body)
    start_ns, end_ns, size = fields.uint(8), fields.uint(8), fields.uint(8)
    fields.uint(4)  # CRC of the uncompressed records, not checked (the mcap library does not either)
    compression = fields.text()
    stated = fields.uint(8)
    data = fields.take(stated) if whole else fields.rest()[:stated]
    return ChunkHead(start_ns, end_ns, size, compression, data)


def _zstd_prefix(data: bytes, limit_bytes: int, *, whole: bool) -> bytes:
    out = bytearray()
    reader = zstandard.ZstdDecompressor().stream_reader(io.BytesIO(data), read_across_frames=True)
    try:
        while len(out) < limit_bytes and (part := reader.read(min(_READ_STEP_BYTES, limit_bytes - len(out)))):
            out += part
    except zstandard.ZstdError as err:
        if whole:
            raise RecordError(f"does not decompress ({err})") from err
    return bytes(out)


def _lz4_prefix(data: bytes, limit_bytes: int, *, whole: bool) -> bytes:
    out = bytearray()
    decompressor = lz4.frame.LZ4FrameDecompressor()
    feed = data
    try:
        while len(out) < limit_bytes:
            part = bytes(decompressor.decompress(feed, max_length=min(_READ_STEP_BYTES, limit_bytes - len(out))))
            feed = b""
            if not part:
                break
            out += part
    except RuntimeError as err:
        if whole:
            raise RecordError(f"does not decompress ({err})") from err
    return bytes(out)


def chunk_content(head: ChunkHead, *, whole: bool) -> bytes:
    """The uncompressed records: all of them, or for a cut chunk the prefix that can be rebuilt."""
    limit = head.uncompressed_bytes
    if head.compression == "":
        content = head.data if whole else head.data[:limit]
    elif head.compression == "zstd":
        content = _zstd_prefix(head.data, limit, whole=whole)
    elif head.compression == "lz4":
        content = _lz4_prefix(head.data, limit, whole=whole)
    else:
        raise RecordError(f"uses compression {head.compression!r}, which bagmcp cannot read (zstd, lz4 or none)")
    if whole and len(content) != limit:
        raise RecordError(f"holds {len(content):,} bytes of records where it states {limit:,}")
    return content


def inner_records(content: bytes, *, whole: bool) -> Iterator[tuple[int, bytes]]:
    """(opcode, body) of the records in a chunk's content; stops at the first incomplete one of a cut chunk."""
    at = 0
    while at < len(content):
        if len(content) - at < HEAD_BYTES:
            length = None
        else:
            opcode, length = struct.unpack_from("<BQ", content, at)
        if length is None or length > len(content) - at - HEAD_BYTES:
            if whole:
                raise RecordError(f"holds a record at {at:,} bytes into its content that runs past the chunk's end")
            return
        yield opcode, content[at + HEAD_BYTES : at + HEAD_BYTES + length]
        at += HEAD_BYTES + length


def parse(opcode: int, body: bytes) -> Schema | Channel | Message | None:
    """A schema, channel or message from its record body; None for other kinds of records."""
    fields = Cursor(body)
    if opcode == Opcode.MESSAGE:
        channel_id, sequence, log_ns, publish_ns = fields.uint(2), fields.uint(4), fields.uint(8), fields.uint(8)
        return Message(
            channel_id=channel_id, sequence=sequence, log_time=log_ns, publish_time=publish_ns, data=fields.rest()
        )
    if opcode == Opcode.SCHEMA:
        schema_id, name, encoding = fields.uint(2), fields.text(), fields.text()
        return Schema(id=schema_id, name=name, encoding=encoding, data=fields.take(fields.uint(4)))
    if opcode == Opcode.CHANNEL:
        channel_id, schema_id, topic, encoding = fields.uint(2), fields.uint(2), fields.text(), fields.text()
        pairs = Cursor(fields.take(fields.uint(4)))
        metadata: dict[str, str] = {}
        while pairs.at < len(pairs.data):
            key = pairs.text()
            metadata[key] = pairs.text()
        return Channel(id=channel_id, schema_id=schema_id, topic=topic, message_encoding=encoding, metadata=metadata)
    return None
