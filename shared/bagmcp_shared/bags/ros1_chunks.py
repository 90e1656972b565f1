"""ROS 1 chunk headers, chunks decompressed within the memory budget, and the message records of a chunk.

rosbags decompresses a whole chunk with ``bz2.decompress`` or ``lz4.frame.decompress`` to read a message
from it, with no bound: bz2 turns a run of one byte into a few hundred bytes per gigabyte, so a chunk of a
few kilobytes can hold gigabytes. Each chunk's ``size`` field is checked against the budget when the bag is
opened, and its decompressor is replaced by one that stops at the budget, which also holds for a chunk whose
``size`` field lies.
"""

from __future__ import annotations

import bz2
import struct
from collections.abc import Callable, Collection
from pathlib import Path
from typing import BinaryIO

import lz4.frame  # type: ignore[import-untyped]
from rosbags.rosbag1.reader import Chunk

from bagmcp_shared.budget import check_record, record_refused

_U32 = struct.Struct("<I")
COMPRESSED = ("bz2", "lz4")  # the chunk compressions a ROS 1 bag may use besides "none"
Decompress = Callable[[bytes], bytes]
_MSGDATA = b"\x02"  # the op of a message record


def header_field(record: bytes, name: bytes) -> bytes:
    """The value of field ``name`` in a record header (length-prefixed ``name=value`` fields), b"" when it has
    none; struct.error or ValueError for a header that does not parse."""
    return _fields(record, 0, len(record)).get(name, b"")


def chunk_header(file: BinaryIO, pos: int) -> tuple[str, int]:
    """(compression, declared uncompressed bytes) of the chunk record at ``pos``; raises struct.error, ValueError
    or OSError when the header is not there."""
    file.seek(pos)
    (size,) = struct.unpack("<I", file.read(4))
    header = file.read(size)
    declared = header_field(header, b"size")
    return header_field(header, b"compression").decode("ascii", "replace"), int.from_bytes(declared[:4], "little")


def _bz2_streams(data: bytes, max_length: int) -> bytes:
    """Concatenated bz2 streams, as ``bz2.decompress`` reads them, stopping at ``max_length`` bytes; EOFError
    for a stream cut short, as ``bz2.decompress`` raises."""
    out, rest = bytearray(), data
    while rest and len(out) < max_length:
        decompressor = bz2.BZ2Decompressor()
        out += decompressor.decompress(rest, max_length=max_length - len(out))
        if not decompressor.eof:
            if len(out) < max_length:
                raise EOFError("Compressed data ended before the end-of-stream marker was reached")
            break
        rest = decompressor.unused_data
    return bytes(out)


def chunk_decompressor(bag: Path, pos: int, compression: str, *, declared: int, compressed: int) -> Decompress:
    """The decompressor of the bz2 or lz4 chunk at ``pos`` of ``bag`` (named in errors), within the budget: the
    chunk is refused at once when its declared size is past the limit, and its decompression stops there."""
    where = f"{bag}: the {compression} chunk at byte {pos:,}"
    limit = check_record(where, declared_bytes=declared, compressed_bytes=compressed)
    return _bounded(compression, limit, where)


def _bounded(compression: str, limit: int, where: str) -> Decompress:
    """A decompressor of ``compression`` (bz2 or lz4) chunks that stops past ``limit`` bytes, refusing the chunk
    (``where`` names it), and raises EOFError for data cut short, as ``bz2.decompress`` and
    ``lz4.frame.decompress`` do."""

    def decompress(data: bytes) -> bytes:
        out = _bz2_streams(data, limit + 1) if compression == "bz2" else _lz4_frame(data, limit + 1)
        if len(out) > limit:
            raise record_refused(where, f"holds more than {limit:,} bytes uncompressed in {len(data):,} compressed")
        return out

    return decompress


def _lz4_frame(data: bytes, max_length: int) -> bytes:
    """An lz4 frame decompressed up to ``max_length`` bytes; EOFError for a frame cut short (the streaming
    decompressor returns what it has without a word, where ``lz4.frame.decompress`` raised)."""
    decompressor = lz4.frame.LZ4FrameDecompressor()
    out = bytes(decompressor.decompress(data, max_length=max_length))
    if not decompressor.eof and len(out) < max_length:
        raise EOFError("the lz4 frame ended before its end mark")
    return out


def bound_chunks(path: Path, chunks: dict[int, Chunk]) -> list[str]:
    """Check every compressed chunk's declared size and bound its decompression (``chunks`` is rosbags'
    table, changed in place); returns each chunk's compression name."""
    names = []
    with path.open("rb") as file:
        for pos, chunk in chunks.items():
            compression, declared = chunk_header(file, pos)
            names.append(compression)
            if compression in COMPRESSED:
                bounded = chunk_decompressor(path, pos, compression, declared=declared, compressed=chunk.datasize)
                chunks[pos] = chunk._replace(decompressor=bounded)
    return names


def message_records(raw: bytes, wanted: Collection[int]) -> list[tuple[int, int, int, bytes]]:
    """(log time, offset, connection, bytes) of the messages of ``wanted`` in a decompressed chunk, in file order.

    Parsed with struct on the bytes in place, not with rosbags' ``Header.read`` over a BytesIO: the corpus's
    two_robots.bag (3.5 MB, 13,325 messages) opened with ``Ros1RangeSource`` over its bytes in a BytesIO and
    read whole took 42 ms instead of 151 ms (in process, best of 5, with the bounds read once, see
    ``Ros1RangeSource.bounds``). Raises struct.error, KeyError or ValueError for a record that does not parse or
    runs past the chunk's end."""
    found: list[tuple[int, int, int, bytes]] = []
    pos, end = 0, len(raw)
    while pos < end:
        (header_bytes,) = _U32.unpack_from(raw, pos)
        fields_end = pos + 4 + header_bytes
        (data_bytes,) = _U32.unpack_from(raw, fields_end)
        data_at = fields_end + 4
        if data_at + data_bytes > end:
            raise ValueError(f"the record at byte {pos:,} of the chunk runs past its end")
        fields = _fields(raw, pos + 4, fields_end)
        if len(op := fields[b"op"]) != 1:
            raise ValueError(f"the record at byte {pos:,} of the chunk has an op field of {len(op)} bytes")
        if op == _MSGDATA and (conn_id := _U32.unpack_from(fields[b"conn"])[0]) in wanted:
            secs, nsecs = struct.unpack("<II", fields[b"time"])
            found.append((secs * 1_000_000_000 + nsecs, pos, conn_id, raw[data_at : data_at + data_bytes]))
        pos = data_at + data_bytes
    return found


def _fields(raw: bytes, start: int, stop: int) -> dict[bytes, bytes]:
    """A record header's ``name=value`` fields between ``start`` and ``stop``."""
    fields: dict[bytes, bytes] = {}
    while start < stop:
        (size,) = _U32.unpack_from(raw, start)
        start += 4
        if start + size > stop:
            raise ValueError("a header field runs past its header")
        name, sep, value = raw[start : start + size].partition(b"=")
        if not sep:
            raise ValueError("a header field has no '='")
        fields[name] = value
        start += size
    return fields
