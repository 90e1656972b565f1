"""One pass over an MCAP file from start to end: what it holds, and where it is cut or damaged.

A file whose last record runs past its end is cut short. Everything in complete records before
it is read; from a cut chunk the complete messages at its start are recovered too (compressed
chunks through a streaming decompressor, which rebuilds the bytes that are there). A record that
is there but cannot be read (garbage, an unknown compression) ends the pass the same way.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import BinaryIO

from mcap.opcode import Opcode
from mcap.records import Channel, Message, Schema

from bagmcp_shared.bags.mcap_records import (
    ChunkHead,
    Piece,
    RecordError,
    chunk_content,
    chunk_head,
    inner_records,
    parse,
    pieces,
)
from bagmcp_shared.budget import check_record

_PLAUSIBLE_RECORD_BYTES = 1 << 40  # a longer record is garbage, not a recording cut short
Item = Piece | Schema | Channel | Message


def cut_chunk_head(piece: Piece) -> ChunkHead | None:
    """A chunk's fields, when all of them are there (also before the cut of a chunk cut short)."""
    try:
        return chunk_head(piece.body, whole=piece.complete)
    except RecordError:
        return None


def _contents(piece: Piece) -> Iterator[Schema | Channel | Message]:
    if piece.opcode == 0:
        raise RecordError("is not an MCAP record (no record has opcode 0x00)")
    if not piece.complete and (piece.claimed_bytes or 0) > _PLAUSIBLE_RECORD_BYTES:
        raise RecordError(f"claims a length of {piece.claimed_bytes:,} bytes, so it is not an MCAP record")
    if piece.opcode == Opcode.CHUNK:
        head = chunk_head(piece.body, whole=True) if piece.complete else cut_chunk_head(piece)
        if head is None:
            return
        if head.compression:  # refused before anything is decompressed (BAGMCP_MAX_RECORD_BYTES)
            where = f"the {head.compression} chunk at byte {piece.offset:,}"
            check_record(where, declared_bytes=head.uncompressed_bytes, compressed_bytes=len(head.data))
        for opcode, body in inner_records(chunk_content(head, whole=piece.complete), whole=piece.complete):
            if (record := parse(opcode, body)) is not None:
                yield record
    elif piece.complete and piece.opcode is not None and (record := parse(piece.opcode, piece.body)) is not None:
        yield record


def stream(file: BinaryIO, size_bytes: int) -> Iterator[Item]:
    """Each top-level record, then the schemas, channels and messages it holds, in file order.

    Raises :class:`RecordError` (completing "the record that starts at ...") for a damaged record.
    """
    for piece in pieces(file, size_bytes):
        yield piece
        yield from _contents(piece)


@dataclass(frozen=True)
class Cut:
    """The record the file ends inside (or the damaged one), and what was read before and from it."""

    piece: Piece
    size_bytes: int
    before: int  # complete messages before the record
    inside: int  # complete messages recovered from inside it
    topics: tuple[str, ...]  # the topics of those inside it
    after_data: bool  # the record is in the summary section: every message is complete
    damage: str = ""  # why a record that is there cannot be read; empty when the file is cut short


@dataclass
class Scan:
    """What one pass over the file learned."""

    schemas: dict[int, Schema] = field(default_factory=dict)
    channels: dict[int, Channel] = field(default_factory=dict)
    counts: dict[int, int] = field(default_factory=dict)
    bounds: dict[int, tuple[int, int]] = field(default_factory=dict)
    chunk_compressions: list[str] = field(default_factory=list)
    total: int = 0
    in_last_record: dict[int, int] = field(default_factory=dict)  # messages per channel
    cut: Cut | None = None

    def take(self, item: Schema | Channel | Message) -> None:
        if isinstance(item, Schema):
            self.schemas[item.id] = item
        elif isinstance(item, Channel):
            self.channels[item.id] = item
        else:
            cid = item.channel_id
            self.counts[cid] = self.counts.get(cid, 0) + 1
            self.in_last_record[cid] = self.in_last_record.get(cid, 0) + 1
            self.total += 1
            lo, hi = self.bounds.get(cid, (item.log_time, item.log_time))
            self.bounds[cid] = (min(lo, item.log_time), max(hi, item.log_time))

    def end_at(self, piece: Piece, size_bytes: int, *, after_data: bool, damage: str) -> None:
        inside = sum(self.in_last_record.values())
        topics = tuple(sorted({self.channels[c].topic for c in self.in_last_record if c in self.channels}))
        self.cut = Cut(piece, size_bytes, self.total - inside, inside, topics, after_data, damage)


def scan(file: BinaryIO, size_bytes: int) -> Scan:
    """Read the whole file once; ``cut`` says where it is cut short or damaged, if it is."""
    found = Scan()
    last: Piece | None = None
    data_ended = False
    try:
        for item in stream(file, size_bytes):
            if isinstance(item, Piece):
                last, data_ended = item, data_ended or item.opcode == Opcode.DATA_END
                found.in_last_record = {}
                if item.opcode == Opcode.CHUNK and (head := cut_chunk_head(item)) is not None:
                    found.chunk_compressions.append(head.compression)
            else:
                found.take(item)
    except RecordError as err:
        assert last is not None  # records are read only after their piece
        found.end_at(last, size_bytes, after_data=data_ended, damage=str(err))
        return found
    if last is not None and not last.complete:
        found.end_at(last, size_bytes, after_data=data_ended, damage="")
    return found
