"""A channel's first and last log time in an MCAP file from its message index records, no chunk decompressed.

A summarised file's chunk indexes say which chunks hold a channel (``message_index_offsets``) and where that
channel's message index record lies: a list of (log time, offset) pairs, 16 bytes a message. Reading the
first and last message through the ``mcap`` reader instead decompressed and parsed two whole chunks per
channel (a drive bag's summary spent a sixth of its ingest there, and in team mode each chunk is a ranged read).

Chunks may overlap in time, so the first time is the least over the chunks that start no later than the
best found so far (chunks taken in start order), and the last time likewise from the end. Whatever cannot be
read this way (no message index for the channel, a record that is not one, a length past what the chunk index
allows) gives None, and the caller reads the messages as before, with the errors it reported before.
"""

from __future__ import annotations

import struct
from collections.abc import Callable, Sequence
from typing import BinaryIO

from mcap.opcode import Opcode
from mcap.records import ChunkIndex

_HEAD = struct.Struct("<BQHI")  # opcode, record length, channel id, byte length of the (time, offset) pairs
_PAIR_BYTES = 16


def indexed_bounds(file: BinaryIO, chunks: Sequence[ChunkIndex], channel_id: int) -> tuple[int, int] | None:
    """(first, last) log time of ``channel_id`` from the message indexes of ``chunks``; None when they cannot
    tell (the caller then reads the messages)."""
    holding = [c for c in chunks if channel_id in c.message_index_offsets]
    if not holding:
        return None
    read = _times_reader(file, channel_id)
    first = _extreme(sorted(holding, key=lambda c: c.message_start_time), read, lowest=True)
    last = _extreme(sorted(holding, key=lambda c: c.message_end_time, reverse=True), read, lowest=False)
    if first is None or last is None:
        return None
    return first, last


def _extreme(ordered: list[ChunkIndex], read: Callable[[ChunkIndex], list[int] | None], *, lowest: bool) -> int | None:
    """The least (``lowest``) or greatest time over ``ordered`` chunks (by start time ascending, or end time
    descending), stopping at the first chunk whose start (end) cannot beat the best found."""
    best: int | None = None
    for chunk in ordered:
        edge = chunk.message_start_time if lowest else chunk.message_end_time
        if best is not None and (edge >= best if lowest else edge <= best):
            break
        times = read(chunk)
        if times is None:
            return None
        if times:
            found = min(times) if lowest else max(times)
            best = found if best is None else min(best, found) if lowest else max(best, found)
    return best


def _times_reader(file: BinaryIO, channel_id: int) -> Callable[[ChunkIndex], list[int] | None]:
    def read(chunk: ChunkIndex) -> list[int] | None:
        """The log times of the channel's message index in ``chunk``; None when the record is not one."""
        file.seek(chunk.message_index_offsets[channel_id])
        head = file.read(_HEAD.size)
        if len(head) != _HEAD.size:
            return None
        opcode, length, channel, pairs = _HEAD.unpack(head)
        if (
            opcode != Opcode.MESSAGE_INDEX
            or channel != channel_id
            or length != 6 + pairs
            or pairs % _PAIR_BYTES
            or pairs > chunk.message_index_length
        ):
            return None
        body = file.read(pairs)
        if len(body) != pairs:
            return None
        return [time for time, _offset in struct.iter_unpack("<QQ", body)]

    return read
