"""Team mode's bag files with range reads: bare MCAP files, ROS 1 bags and ROS 2 directories of MCAP or
sqlite3 storage files are read where they are stored.

A point read of an MCAP bag fetches its header block, its footer and summary (chunk indexes) and the
chunks that overlap the topic and window; of a ROS 1 bag, its header, the index at its end (connections
and chunk infos) and the chunks that overlap; all through the host's block cache, nothing copied whole.
A ROS 2 directory of MCAP storage files is read the same way per file, metadata.yaml as one small read;
a sqlite3 storage file (.db3) page by page, as SQLite asks for its pages (bags/sqlite3_stream.py: an apsw
VFS over the same ranged file), each topic's count and bounds taken from the catalog instead of a scan of
every row (ingest, which has no catalog summary yet, scans: it streams each .db3 through the block cache).
ROS 2 directories with zstd-compressed (.mcap.zstd, .db3.zstd) storage files are still copied whole by
``CachedBagFiles`` (a zstd stream cannot be entered in the middle), and other formats (ULog, DataFlash).
Ingest reads ranged bags by range too (their format from their first bytes, or a directory's from its file
names); the others it copies whole, and drops the copy afterwards (``drop_copy``). Downloads stream from
the object store (``parts_of``)."""

from __future__ import annotations

from collections.abc import Callable
from functools import partial
from pathlib import Path
from typing import BinaryIO, Protocol, cast

from bagmcp_shared import keys
from bagmcp_shared.access.blocks import BlockCache
from bagmcp_shared.access.files import CachedBagFiles, at_once
from bagmcp_shared.access.ranged import UNKNOWN_SIZE, RangedFile, RangeStore, StoredFile, changed
from bagmcp_shared.bags import BagFormat, BagReader, open_directory_stream, open_stream
from bagmcp_shared.bags.detect import format_of_head
from bagmcp_shared.bags.source import TopicTotals
from bagmcp_shared.catalog.models import BagRecord
from bagmcp_shared.settings import RangeReads
from bagmcp_shared.storage import ObjectStore


class RemoteStore(ObjectStore, RangeStore, Protocol):
    """An object store that also answers ranged reads with the object's ETag (S3Store)."""


class RangedBagFiles(CachedBagFiles):
    """``CachedBagFiles`` whose readers of ``ranged`` bags (MCAP, ROS 1, ROS 2 MCAP or sqlite3) read through
    ``blocks``."""

    def __init__(self, store: RemoteStore, cache_dir: Path, *, max_bytes: int, reads: RangeReads) -> None:
        self.blocks = BlockCache(
            cache_dir / ".blocks", block_bytes=reads.block_bytes, max_bytes=reads.cache_bytes
        )  # a dot name: the whole-copy cache neither counts nor evicts it
        super().__init__(store, cache_dir, max_bytes=max_bytes, counters=self.blocks.counters)
        self._ranges = store
        self._read_ahead = reads.read_ahead_bytes

    def reader_for(self, record: BagRecord) -> tuple[Path, Callable[[], BagReader]]:
        """By range when the bag's format reads so (ingest too: the format of a bag not yet ingested comes
        from its first bytes, so ingest streams it through the block cache instead of copying it whole)."""
        fmt = self._ranged_format(record)
        if fmt is None or self.has_copy(record):  # a process holding a whole copy reads it
            return super().reader_for(record)
        label = Path(record.name)
        if record.layout == "directory":
            return label, lambda: self._open_directory(record, label)
        stored = self._stored(record)
        return label, lambda: open_stream(label, cast(BinaryIO, self._ends_fetched(stored)), size=stored.size, fmt=fmt)

    def _ends_fetched(self, stored: StoredFile) -> RangedFile:
        """A bag file opened with its header and its end (index or summary) fetched at once."""
        file = self.open_file(stored)
        try:
            file.prefetch_ends()
        except BaseException:
            file.close()
            raise
        return file

    def _stored(self, record: BagRecord) -> StoredFile:
        name = record.files[0]
        return StoredFile(record.name, keys.bag_file(record.id, name), record.size_bytes, record.etags.get(name, ""))

    def _ranged_format(self, record: BagRecord) -> BagFormat | None:
        """The format a ranged reader opens the bag as, or None when it is read from a whole copy."""
        if record.summary is not None:
            return BagFormat(record.summary.format) if ranged(record) else None
        if record.layout == "directory":
            return _directory_format(record)
        with self.open_file(self._stored(record)) as file:
            fmt = format_of_head(file.read(16))
        return fmt if fmt in RANGED else None

    def release_ingested(self, record: BagRecord) -> bool:
        """A bag read by range needs no whole copy after ingest: the one ingest fetched is dropped at once,
        so no process keeps a whole copy (later reads, in this worker too, fetch ranges)."""
        return ranged(record) and self.drop_copy(record)

    def _open_directory(self, record: BagRecord, label: Path) -> BagReader:
        """A ROS 2 directory of MCAP or sqlite3 storage files: metadata.yaml read whole (a few KB, through the
        block cache like the rest), each storage file opened by range; the catalog's per-topic totals stand
        in for sqlite3 files' scans of every row. What each file's reader reads first is fetched at once with
        the others' (``_first_reads``): one round trip for the directory, not one per file."""
        files: dict[str, RangedFile] = {}
        try:
            for name in record.files:
                size = record.file_sizes.get(name, UNKNOWN_SIZE)
                stored = StoredFile(record.name, keys.bag_file(record.id, name), size, record.etags.get(name, ""))
                files[Path(name).name] = self.open_file(stored)
            at_once([partial(_first_reads, name, file) for name, file in files.items()])
            if (found := sum(file.size for file in files.values())) != record.size_bytes:
                raise changed(record.name, f"{found} bytes in all, the catalog recorded {record.size_bytes}")
            metadata = None
            if (listed := files.pop(METADATA, None)) is not None:
                with listed:
                    metadata = listed.read()
        except BaseException:
            for file in files.values():
                file.close()
            raise
        storage = {name: (cast(BinaryIO, file), file.size) for name, file in files.items()}
        return open_directory_stream(label, metadata, storage, totals=topic_totals(record))

    def open_file(self, stored: StoredFile) -> RangedFile:
        """A seekable file over ``stored``, read through the block cache."""
        return RangedFile(self._ranges, stored, self.blocks, read_ahead_bytes=self._read_ahead)


def _first_reads(name: str, file: RangedFile) -> None:
    """Fetch what a reader of a directory's file reads first, at once with the other files': an MCAP file's
    header and summary at its end when the catalog recorded its size, else its first block (which brings the
    size when the catalog has none). With sizes recorded a cold MCAP point read makes two round trips, not
    three (the summary waited for the first block's answer to learn where the file ends)."""
    if name.endswith(".mcap") and file.size_known:
        file.prefetch_ends()
    else:
        file.prefetch_head()


RANGED = frozenset({BagFormat.MCAP, BagFormat.ROS1})
RANGED_ROS2 = frozenset({BagFormat.ROS2_MCAP, BagFormat.ROS2_SQLITE3})
METADATA = "metadata.yaml"


def ranged(record: BagRecord) -> bool:
    """Whether the bag is read by range: ingested, and a single bare MCAP file or ROS 1 bag, or a ROS 2
    directory whose storage files are all uncompressed-by-file MCAP (``.mcap``) or sqlite3 (``.db3``) files."""
    if record.summary is None:
        return False
    if record.layout == "file":
        return record.summary.format in RANGED
    return record.summary.format in RANGED_ROS2 and _directory_format(record) is not None


def _directory_format(record: BagRecord) -> BagFormat | None:
    """ROS2_SQLITE3 or ROS2_MCAP for a ROS 2 directory whose storage files are all plain ``.db3`` or ``.mcap``
    files (``.db3`` files all, or not all), else None. A directory stored with other files (one without
    metadata.yaml keeps all it came with) stays copied whole: a ``.db3-wal`` beside its database holds rows
    SQLite reads from a local copy."""
    storage = [name for name in record.files if Path(name).name != METADATA]
    if not storage or not all(name.endswith((".mcap", ".db3")) for name in storage):
        return None
    return BagFormat.ROS2_SQLITE3 if all(name.endswith(".db3") for name in storage) else BagFormat.ROS2_MCAP


def topic_totals(record: BagRecord) -> TopicTotals | None:
    """Each topic's count and first/last log time as ingest recorded them (from these very files)."""
    if record.summary is None:
        return None
    return {topic.name: (topic.count, topic.first_ns, topic.last_ns) for topic in record.summary.topics}
