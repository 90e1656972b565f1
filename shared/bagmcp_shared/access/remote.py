"""Team mode's bag files with range reads: bare MCAP files and ROS 1 bags are read where they are stored.

A point read of an MCAP bag fetches its header block, its footer and summary (chunk indexes) and the
chunks that overlap the topic and window; of a ROS 1 bag, its header, the index at its end (connections
and chunk infos) and the chunks that overlap; all through the host's block cache, nothing copied whole.
ROS 2 directories (sqlite3 or MCAP storage) are still copied whole by ``CachedBagFiles`` (rosbags and
sqlite3 open them by path), as is every bag while it is ingested, and for downloads.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import BinaryIO, Protocol, cast

from bagmcp_shared import keys
from bagmcp_shared.access.blocks import BlockCache
from bagmcp_shared.access.files import CachedBagFiles
from bagmcp_shared.access.ranged import RangedFile, RangeStore, StoredFile
from bagmcp_shared.bags import BagFormat, BagReader, open_stream
from bagmcp_shared.catalog.models import BagRecord
from bagmcp_shared.settings import RangeReads
from bagmcp_shared.storage import ObjectStore


class RemoteStore(ObjectStore, RangeStore, Protocol):
    """An object store that also answers ranged reads with the object's ETag (S3Store)."""


class RangedBagFiles(CachedBagFiles):
    """``CachedBagFiles`` whose readers of bare MCAP files and ROS 1 bags read by range through ``blocks``."""

    def __init__(self, store: RemoteStore, cache_dir: Path, *, max_bytes: int, reads: RangeReads) -> None:
        super().__init__(store, cache_dir, max_bytes=max_bytes)
        self._ranges = store
        self._read_ahead = reads.read_ahead_bytes
        self.blocks = BlockCache(
            cache_dir / ".blocks", block_bytes=reads.block_bytes, max_bytes=reads.cache_bytes
        )  # a dot name: the whole-copy cache neither counts nor evicts it

    def reader_for(self, record: BagRecord) -> tuple[Path, Callable[[], BagReader]]:
        if not ranged(record) or self.has_copy(record):  # a worker that ingested the bag reads its copy
            return super().reader_for(record)
        name = record.files[0]
        stored = StoredFile(record.name, keys.bag_file(record.id, name), record.size_bytes, record.etags.get(name, ""))
        label = Path(record.name)
        fmt = BagFormat(record.summary.format if record.summary is not None else "")
        return label, lambda: open_stream(label, cast(BinaryIO, self.open_file(stored)), size=stored.size, fmt=fmt)

    def open_file(self, stored: StoredFile) -> RangedFile:
        """A seekable file over ``stored``, read through the block cache."""
        return RangedFile(self._ranges, stored, self.blocks, read_ahead_bytes=self._read_ahead)


RANGED = frozenset({BagFormat.MCAP, BagFormat.ROS1})


def ranged(record: BagRecord) -> bool:
    """Whether the bag is read by range: a single bare MCAP file or ROS 1 bag, ingested."""
    return record.layout == "file" and record.summary is not None and record.summary.format in RANGED
