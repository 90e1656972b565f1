"""An indexed MCAP's compressed chunks checked against the memory budget when the file is opened.

The ``mcap`` library decompresses a whole chunk into memory to read one message from it, trusting the size
the chunk record declares (``zstandard.decompress(data, uncompressed_size)``), so a 16.6 KB file whose one
zstd chunk declares 512 MiB cost 1.3 GB per process that read it. Both the chunk index (what the summary
says) and the chunk record itself (what the library reads) are checked; reading the ~60 bytes of each
chunk's head costs one seek per chunk: 10 ms for 4,020 chunks here (file in the page cache).
An lz4 chunk that declares less than its frame holds is not caught here: the library's lz4 call trusts the
frame alone, and mcap_lz4_bound stops it at the budget while it is read.
Uncompressed chunks are not checked: what they hold is on disk, bounded by the file's size.
"""

from __future__ import annotations

import struct
from collections.abc import Sequence
from typing import BinaryIO

from mcap.records import ChunkIndex

from bagmcp_shared.bags.mcap_records import HEAD_BYTES
from bagmcp_shared.budget import check_record

_FIXED = struct.Struct("<QQQII")  # start, end, uncompressed size, CRC, compression name length
_MAX_NAME_BYTES = 64


def _record_sizes(file: BinaryIO, offset: int) -> tuple[int, int] | None:
    """(declared uncompressed bytes, compressed bytes) from the chunk record at ``offset``; None when the
    head does not parse (the library reports that damage when it reads the chunk)."""
    file.seek(offset + HEAD_BYTES)
    fixed = file.read(_FIXED.size)
    if len(fixed) < _FIXED.size:
        return None
    _start, _end, uncompressed, _crc, name_bytes = _FIXED.unpack(fixed)
    if name_bytes > _MAX_NAME_BYTES:
        return None
    rest = file.read(name_bytes + 8)
    if len(rest) < name_bytes + 8:
        return None
    (compressed,) = struct.unpack_from("<Q", rest, name_bytes)
    return uncompressed, compressed


def check_chunks(file: BinaryIO, indexes: Sequence[ChunkIndex], *, read_records: bool = True) -> None:
    """Refuse the file (UnsupportedFormatError naming the chunk) when a compressed chunk may expand past
    the budget, as its index or (``read_records``) its own record declares."""
    for index in indexes:
        if not index.compression:
            continue
        where = f"the {index.compression} chunk at byte {index.chunk_start_offset:,}"
        check_record(where, declared_bytes=index.uncompressed_size, compressed_bytes=index.compressed_size)
        if read_records and (sizes := _record_sizes(file, index.chunk_start_offset)) is not None:
            check_record(where, declared_bytes=sizes[0], compressed_bytes=sizes[1])
