"""The views' rows in memory: each bag's file of a view is read once per process (one GET, in parallel when
many are missing) and kept while it fits ``max_bytes`` (least recently used dropped first); a view over many
bags is those tables joined end to end, remembered until the set of bags changes. 500 short bags' poses
are about 60 MB; a warm query pays only DuckDB's scan of them.
"""

from __future__ import annotations

import logging
import threading
from collections import OrderedDict
from collections.abc import Callable, Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field

import pyarrow as pa

from bagmcp_bag_store.errors import QueryStoppedError
from bagmcp_bag_store.fleet.files import FleetFiles, has_views
from bagmcp_bag_store.fleet.views import VIEWS
from bagmcp_shared.catalog import BagRecord
from bagmcp_shared.errors import BagmcpError

log = logging.getLogger(__name__)

LOADERS = 8  # concurrent reads of missing files (S3 GETs of a few KB: latency-bound)
Progress = Callable[[float, str], None]


Key = tuple[tuple[str, str, bool], ...]  # (id, name, views written) of each bag of a view


def _key(bags: Sequence[BagRecord]) -> Key:
    return tuple((b.id, b.name, has_views(b)) for b in bags)


@dataclass
class Joined:
    """A view's rows over the chosen bags, and the bags whose files are not stored (yet)."""

    table: pa.Table
    missing: list[str] = field(default_factory=list)


class FleetTables:
    def __init__(self, files: FleetFiles, *, max_bytes: int) -> None:
        self._files = files
        self._max_bytes = max_bytes
        self._tables: OrderedDict[tuple[str, str], pa.Table] = OrderedDict()
        self._joined: dict[str, tuple[Key, Joined]] = {}
        self._bytes = 0
        self._lock = threading.Lock()
        self._reading = {kind: threading.Lock() for kind in VIEWS}  # one reader of a view's files at a time
        self._prefetching: set[str] = set()

    def warm(self, kind: str, bags: Sequence[BagRecord]) -> bool:
        """Whether every bag's rows of ``kind`` are in memory (a query over them needs no reads)."""
        with self._lock:
            return all((kind, b.id) in self._tables for b in bags)

    def view(self, kind: str, bags: Sequence[BagRecord], progress: Progress | None = None) -> Joined:
        key = _key(bags)
        with self._lock:
            remembered = self._joined.get(kind)
            if remembered is not None and remembered[0] == key and not remembered[1].missing:
                return remembered[1]
        parts, missing = self._parts(kind, bags, progress)
        joined = Joined(pa.concat_tables([VIEWS[kind].empty, *parts]), missing)
        with self._lock:
            self._joined[kind] = (key, joined)
        return joined

    def prefetch(self, kind: str, bags: Sequence[BagRecord]) -> None:
        """Read the bags' files of ``kind`` in the background (one at a time per view): a query over cold views
        runs as a job, maybe in another process, while this one warms up for the next."""
        with self._lock:
            if kind in self._prefetching:
                return
            self._prefetching.add(kind)
        threading.Thread(target=self._prefetched, args=(kind, list(bags)), name=f"prefetch-{kind}", daemon=True).start()

    def _prefetched(self, kind: str, bags: list[BagRecord]) -> None:
        try:
            self._parts(kind, bags, None)
        except BagmcpError as err:  # too large for the cache, or storage down: the query itself says so
            log.info("prefetching %s stopped: %s", kind, err)
        finally:
            with self._lock:
                self._prefetching.discard(kind)

    def _parts(
        self, kind: str, bags: Sequence[BagRecord], progress: Progress | None
    ) -> tuple[list[pa.Table], list[str]]:
        with self._reading[kind]:  # a second reader finds what the first read
            with self._lock:
                found = {b.id: self._touch((kind, b.id)) for b in bags}
            absent = [b for b in bags if found[b.id] is None]
            for done, (bag, table) in enumerate(self._load(kind, absent), start=1):
                found[bag.id] = table
                if progress is not None and done % 25 == 0:
                    progress(done / len(absent), f"read {done} of {len(absent)} bags' {kind}")
        needed = sum(t.nbytes for t in found.values() if t is not None)
        if needed > self._max_bytes:
            raise QueryStoppedError(
                f"the {kind} rows of these {len(bags)} bags take {needed / 2**20:.0f} MiB, more than the query cache "
                f"holds ({self._max_bytes / 2**20:.0f} MiB, BAGMCP_QUERY_CACHE_BYTES); filter to fewer bags with "
                "find_bags or a tag, or raise the limit"
            )
        parts = [_named(t, b.name) for b in bags if (t := found[b.id]) is not None]
        return parts, [b.name for b in bags if found[b.id] is None]

    def _load(self, kind: str, bags: list[BagRecord]) -> list[tuple[BagRecord, pa.Table | None]]:
        if not bags:
            return []
        with ThreadPoolExecutor(max_workers=min(LOADERS, len(bags))) as pool:
            loaded = list(zip(bags, pool.map(lambda b: self._files.read(kind, b), bags), strict=True))
        with self._lock:
            for bag, table in loaded:
                if table is not None:
                    self._keep((kind, bag.id), table)
        return loaded

    def _touch(self, key: tuple[str, str]) -> pa.Table | None:
        table = self._tables.get(key)
        if table is not None:
            self._tables.move_to_end(key)
        return table

    def _keep(self, key: tuple[str, str], table: pa.Table) -> None:
        if key in self._tables:
            return
        self._tables[key] = table
        self._bytes += table.nbytes
        while self._bytes > self._max_bytes and len(self._tables) > 1:
            _, dropped = self._tables.popitem(last=False)
            self._bytes -= dropped.nbytes

    def forget(self, bag_id: str) -> None:
        """Drop a deleted bag's rows."""
        with self._lock:
            for key in [k for k in self._tables if k[1] == bag_id]:
                self._bytes -= self._tables.pop(key).nbytes
            self._joined.clear()


def _named(table: pa.Table, name: str) -> pa.Table:
    """The bag's rows under its current name (a bag listed again after a lost catalog may be renamed)."""
    if not table.num_rows or table.column("bag")[0].as_py() == name:
        return table
    index = table.schema.get_field_index("bag")
    return table.set_column(index, "bag", pa.array([name] * table.num_rows, type=pa.string()))
