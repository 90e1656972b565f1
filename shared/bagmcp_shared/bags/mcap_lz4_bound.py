"""The ``mcap`` library's lz4 chunk decompression, bounded by the memory budget.

The library reads an lz4 chunk with ``lz4.frame.decompress(chunk.data)`` (the name ``lz4`` in
``mcap.stream_reader``), which trusts only the frame: a chunk whose record declares a few bytes (and so
passes the checks in mcap_chunk_budget) may still expand about 255 times its compressed size. That name is
pointed, once, at :class:`BoundedLz4Frame`, which decompresses the same frame but stops at the budget's
limit for the chunk's compressed size. (zstd chunks need no such help: the library passes the declared size
as zstd's output bound, and that size is checked when the file is opened.)
"""

from __future__ import annotations

import lz4.frame  # type: ignore[import-untyped]
import mcap.stream_reader

from bagmcp_shared.budget import input_budget, record_refused


class BoundedLz4Frame:
    """``lz4.frame``'s ``decompress`` as the mcap library calls it, within the budget."""

    @staticmethod
    def decompress(data: bytes) -> bytes:
        limit = input_budget().record_limit(len(data))
        out = bytes(lz4.frame.LZ4FrameDecompressor().decompress(data, max_length=limit + 1))
        if len(out) > limit:
            raise record_refused(
                "an lz4 chunk", f"holds more than {limit:,} bytes uncompressed in {len(data):,} compressed"
            )
        return out


def bound_library_lz4() -> None:
    """Make the mcap library decompress lz4 chunks through :class:`BoundedLz4Frame` (idempotent)."""
    mcap.stream_reader.lz4 = BoundedLz4Frame  # type: ignore[attr-defined]
