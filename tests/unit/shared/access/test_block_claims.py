"""A fetch run's block locks (BlockCache.claim): blocks are locked by stripe, so two blocks of one run can share a
lock; the run holds it already and must not stop there (one chunk's read came in two S3 requests in about a third
of cold MCAP point reads, the stripes depending on the bucket's name)."""

from __future__ import annotations

import zlib
from pathlib import Path

from bagmcp_shared.access.blocks import STRIPES, BlockCache

OBJ = "5d41402abc4b2a76b9719d911017c592"  # an object id: a hash of bucket, key and ETag


def _stripe(index: int) -> int:
    return zlib.crc32(f"{OBJ}/{index}".encode()) % STRIPES


def test_a_run_whose_blocks_share_a_lock_stripe_is_claimed_whole(tmp_path: Path) -> None:
    twin = next(i for i in range(1, 10 * STRIPES) if _stripe(i) == _stripe(0))
    cache = BlockCache(tmp_path, block_bytes=16, max_bytes=1 << 20)
    with cache.claim(OBJ, 0, twin + 3) as end:
        assert end == twin + 3


def test_a_run_stops_before_a_block_that_is_on_disk_or_locked_by_another_run(tmp_path: Path) -> None:
    cache = BlockCache(tmp_path, block_bytes=16, max_bytes=1 << 20)
    cache.store(OBJ, 5, [b"x" * 16])
    with cache.claim(OBJ, 0, 9) as end:
        assert end == 4
    other = BlockCache(tmp_path, block_bytes=16, max_bytes=1 << 20)  # another process's view of the same cache
    blocked = next(i for i in range(8, 10 * STRIPES) if _stripe(i) == _stripe(6) != _stripe(i - 1))
    with cache.claim(OBJ, 6, 6) as held:
        assert held == 6
        with other.claim(OBJ, blocked - 1, blocked) as end:
            assert end == blocked - 1  # the next block's lock is another run's: the run ends before it
