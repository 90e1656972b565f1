"""Storing a fetched run of blocks (BlockCache.store): one reservation per run, and still within the bound when
the run is larger than the cache; the shared byte count stays equal to what is on disk."""

from __future__ import annotations

from pathlib import Path

from bagmcp_shared.access.blocks import BlockCache

OBJ = "5d41402abc4b2a76b9719d911017c592"  # an object id: a hash of bucket, key and ETag
BLOCK = 16


def _usage(directory: Path) -> int:
    return int((directory / "usage").read_text())


def test_a_run_is_stored_whole_and_counted_once(tmp_path: Path) -> None:
    cache = BlockCache(tmp_path, block_bytes=BLOCK, max_bytes=1 << 20)
    parts = [bytes([n]) * BLOCK for n in range(5)]
    cache.store(OBJ, 3, parts)
    assert [cache.cached(OBJ, 3 + n) for n in range(5)] == parts
    assert _usage(tmp_path) == cache.used_bytes() == 5 * BLOCK
    cache.store(OBJ, 3, parts)  # fetched again (another process evicted nothing): replaces, not adds
    assert _usage(tmp_path) == cache.used_bytes() == 5 * BLOCK
    assert cache.counters.snapshot()["bagmcp_block_cache_misses_total"] == 10


def test_a_run_larger_than_the_cache_keeps_within_its_bound_and_keeps_its_last_blocks(tmp_path: Path) -> None:
    cache = BlockCache(tmp_path, block_bytes=BLOCK, max_bytes=10 * BLOCK)
    parts = [bytes([n]) * BLOCK for n in range(40)]
    cache.store(OBJ, 0, parts)
    assert cache.used_bytes() <= 10 * BLOCK
    assert _usage(tmp_path) == cache.used_bytes()
    assert cache.cached(OBJ, 39) == parts[39]  # the run's end, which a streaming reader reads next
    assert cache.cached(OBJ, 0) is None
    assert cache.counters.snapshot()["bagmcp_s3_fetched_bytes_total"] == 40 * BLOCK


def test_a_block_larger_than_the_cache_is_counted_and_not_kept(tmp_path: Path) -> None:
    cache = BlockCache(tmp_path, block_bytes=BLOCK, max_bytes=BLOCK - 1)
    cache.store(OBJ, 0, [b"x" * BLOCK])
    assert cache.cached(OBJ, 0) is None
    assert cache.used_bytes() == 0
    assert cache.counters.snapshot()["bagmcp_s3_fetched_bytes_total"] == BLOCK
