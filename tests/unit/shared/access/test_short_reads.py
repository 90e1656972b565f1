"""A range read that comes back short is an error naming the bag, and nothing of it is kept in the block cache.

A real S3 server does not answer a range inside the object with fewer bytes while saying the object's size is
unchanged, so the store here misbehaves on purpose (a broken proxy or server would): it answers every range with
``cut`` bytes fewer, the right ETag and the right size."""

from __future__ import annotations

from pathlib import Path

import pytest

from bagmcp_shared.access.blocks import BlockCache
from bagmcp_shared.access.ranged import RangedFile, StoredFile
from bagmcp_shared.errors import DamagedBagError
from bagmcp_shared.storage import ObjectInfo
from bagmcp_shared.storage.base import RangeAnswer

BLOCK = 4096
ETAG = "0f1e2d3c"


class ShortAnswers:
    """An object store whose ranged reads lose the last ``cut`` bytes of each answer."""

    bucket = "bags"

    def __init__(self, content: bytes, cut: int) -> None:
        self.content = content
        self.cut = cut
        self.requests = 0

    def stat(self, key: str) -> ObjectInfo:
        return ObjectInfo(key, len(self.content), ETAG)

    def read_range_tagged(self, key: str, *, offset: int, length: int) -> RangeAnswer:
        self.requests += 1
        data = self.content[offset : offset + length]
        return RangeAnswer(data[: len(data) - self.cut], ETAG, len(self.content))


@pytest.mark.parametrize("cut", [1, BLOCK])
def test_a_short_answer_is_an_error_naming_the_bag_and_nothing_is_cached(tmp_path: Path, cut: int) -> None:
    content = bytes(range(256)) * 64  # 16 KiB: four blocks
    store = ShortAnswers(content, cut)
    cache = BlockCache(tmp_path, block_bytes=BLOCK, max_bytes=1 << 20)
    stored = StoredFile("drive_0427", "bags/abc/drive_0427.mcap", len(content), ETAG)
    with RangedFile(store, stored, cache, read_ahead_bytes=0) as file:
        file.seek(BLOCK + 10)
        with pytest.raises(DamagedBagError, match=r"^bag drive_0427 changed in the object store .*came back at offset"):
            file.read(100)
    assert store.requests == 1  # a short answer is no transport error: it is not tried again
    assert cache.used_bytes() == 0


def test_a_whole_answer_is_read_and_cached(tmp_path: Path) -> None:
    content = bytes(range(256)) * 64
    store = ShortAnswers(content, 0)
    cache = BlockCache(tmp_path, block_bytes=BLOCK, max_bytes=1 << 20)
    stored = StoredFile("drive_0427", "bags/abc/drive_0427.mcap", len(content), ETAG)
    with RangedFile(store, stored, cache, read_ahead_bytes=0) as file:
        file.seek(BLOCK + 10)
        assert file.read(100) == content[BLOCK + 10 : BLOCK + 110]
    assert cache.used_bytes() == BLOCK
