"""A bounded cache of opened bags, so repeated questions about a bag skip reopening it.

Each entry holds the readers of one bag file (a reader is used by one caller at a time; callers
asking at once get readers of their own, which join the entry when returned) and its columnar
index with the columns loaded so far. Entries are keyed by content id and local path, so a bag
whose content or files change is never answered from a stale reader. The least recently used
entries are closed once the count or the estimated bytes exceed the limits.
"""

from __future__ import annotations

import threading
from collections import OrderedDict
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path

from bagmcp_shared.bags import BagReader, open_bag
from bagmcp_shared.errors import BagmcpError
from bagmcp_shared.index import ColumnIndex
from bagmcp_shared.settings import DEFAULT_OPEN_BAGS, OpenBagLimits

READER_BASE_BYTES = 256 * 1024
BYTES_PER_MESSAGE = 64  # the message and chunk indexes a reader keeps, per message


def reader_bytes(reader: BagReader) -> int:
    """An estimate of what an open reader holds in memory (its indexes), from its message count."""
    return READER_BASE_BYTES + BYTES_PER_MESSAGE * sum(c.count for c in reader.connections)


@dataclass
class _Entry:
    idle: list[BagReader] = field(default_factory=list)
    busy: int = 0
    reader_size: int = 0
    index: ColumnIndex | None = None
    index_loaded: bool = False

    def bytes(self) -> int:
        index = self.index.loaded_bytes() if self.index is not None else 0
        return self.reader_size * (len(self.idle) + self.busy) + index


class ReaderCache:
    """At most ``max_bags`` bags and about ``max_bytes`` of readers and loaded index columns."""

    def __init__(self, limits: OpenBagLimits = DEFAULT_OPEN_BAGS) -> None:
        self.max_bags = limits.max_bags
        self.max_bytes = limits.max_bytes
        self._max_idle = limits.max_readers_per_bag
        self._entries: OrderedDict[tuple[str, Path], _Entry] = OrderedDict()
        self._lock = threading.Lock()
        self.opened = 0  # readers opened since start (tests and the benchmark read it)

    @contextmanager
    def reader(self, bag_id: str, path: Path, opener: Callable[[], BagReader] | None = None) -> Iterator[BagReader]:
        """A reader of ``path`` for this caller alone, opened (by ``opener``, default ``open_bag(path)``)
        only when no idle one is cached."""
        key = (bag_id, path)
        with self._lock:
            entry = self._entries.setdefault(key, _Entry())
            self._entries.move_to_end(key)
            reader = entry.idle.pop() if entry.idle else None
            entry.busy += 1
        try:
            if reader is None:
                reader = opener() if opener is not None else open_bag(path)
                with self._lock:
                    self.opened += 1
                    entry.reader_size = max(entry.reader_size, reader_bytes(reader))
            yield reader
        except BagmcpError:  # the caller's question was wrong, not the reader: keep it
            self._give_back(key, entry, reader, keep=True)
            raise
        except BaseException:
            self._give_back(key, entry, reader, keep=False)
            raise
        self._give_back(key, entry, reader, keep=True)

    def index(self, bag_id: str, path: Path, load: Callable[[], ColumnIndex | None]) -> ColumnIndex | None:
        """The bag's columnar index, loaded once per entry (``load`` finds it on disk)."""
        key = (bag_id, path)
        with self._lock:
            entry = self._entries.setdefault(key, _Entry())
            if entry.index_loaded:
                return entry.index
        index = load()
        with self._lock:
            if not entry.index_loaded:
                entry.index, entry.index_loaded = index, True
            closing, found = self._evict(), entry.index
        for old in closing:  # the readers of bags this index pushed out are closed, not left to the collector
            old.close()
        return found

    def discard(self, bag_id: str) -> None:
        """Forget every entry of ``bag_id`` (deleted or re-ingested); busy readers close when returned."""
        with self._lock:
            doomed = [k for k in self._entries if k[0] == bag_id]
            closing = [r for k in doomed for r in self._entries.pop(k).idle]
        for reader in closing:
            reader.close()

    def close(self) -> None:
        """Close every idle reader and forget every entry (the process is stopping); a reader in use closes
        when it is returned. A reader left to the garbage collector would leave its files open until then,
        and a directory bag's decompressed copy on disk."""
        with self._lock:
            closing = [reader for entry in self._entries.values() for reader in entry.idle]
            self._entries.clear()
        for reader in closing:
            reader.close()

    def total_bytes(self) -> int:
        with self._lock:
            return sum(e.bytes() for e in self._entries.values())

    def __len__(self) -> int:
        with self._lock:
            return len(self._entries)

    def _give_back(self, key: tuple[str, Path], entry: _Entry, reader: BagReader | None, *, keep: bool) -> None:
        closing: list[BagReader] = []
        with self._lock:
            entry.busy -= 1
            if reader is not None:
                current = self._entries.get(key) is entry
                if keep and current and len(entry.idle) < self._max_idle:
                    entry.idle.append(reader)
                else:
                    closing.append(reader)
            closing += self._evict()
        for old in closing:
            old.close()

    def _evict(self) -> list[BagReader]:
        """Drop least recently used entries past the limits (never one in use); returns readers to close."""
        closing: list[BagReader] = []
        total = sum(e.bytes() for e in self._entries.values())
        for key in list(self._entries):
            if len(self._entries) <= self.max_bags and total <= self.max_bytes:
                break
            entry = self._entries[key]
            if entry.busy:
                continue
            total -= entry.bytes()
            closing += self._entries.pop(key).idle
        return closing
