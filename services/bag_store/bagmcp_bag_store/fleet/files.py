"""The columnar store's files: one Parquet file per view per bag in the object store (S3 in team mode, the
data directory's store when embedded), written at ingest, read by queries, removed with the bag.

Why Parquet (pyarrow): it is what DuckDB, Trino, Spark, Polars and MotherDuck all read in place, so the same
files serve ``query_bags`` on one machine and a distributed engine past it; pyarrow writes them from the
index's numpy arrays without copies, and zstd keeps a short bag's files to a few KB each.

Files are read through the project's object store (one GET of a whole file: a view's file of one bag is
small), not DuckDB's httpfs (an extension downloaded at run time, with no network here) nor pyarrow's own S3
filesystem (it would need the S3 settings, CA file and timeouts configured a second time, beside the
store's). The ``bags`` file is written last and removed first: a bag whose ``bags`` file exists has all.
"""

from __future__ import annotations

import io
from collections.abc import Iterator

import pyarrow as pa
import pyarrow.parquet as pq

from bagmcp_bag_store.fleet.extract import EXTRACTORS, IngestedBag
from bagmcp_bag_store.fleet.views import KINDS, VERSION
from bagmcp_shared import keys
from bagmcp_shared.errors import ObjectNotFoundError
from bagmcp_shared.storage import ObjectStore

MARKER = "bags"
_WRITE_ORDER = [k for k in KINDS if k != MARKER] + [MARKER]


def parquet_bytes(table: pa.Table) -> bytes:
    """``table`` as a Parquet file (zstd; row groups of 64k rows, so readers can skip by time)."""
    sink = io.BytesIO()
    pq.write_table(table, sink, compression="zstd", row_group_size=65_536)
    return sink.getvalue()


class FleetFiles:
    def __init__(self, store: ObjectStore) -> None:
        self._store = store

    def complete(self, bag_id: str) -> bool:
        """Whether every view's file of the bag is stored."""
        return self._store.exists(keys.fleet_file(VERSION, MARKER, bag_id))

    def stored_ids(self) -> set[str]:
        """Ids of the bags whose files are all stored (one listing)."""
        prefix = keys.fleet_prefix(VERSION, MARKER)
        return {info.key.removeprefix(prefix).removesuffix(".parquet") for info in self._store.list(prefix)}

    def write(self, bag: IngestedBag) -> int:
        """Store the bag's file of every view (the marker last); returns the bytes written."""
        written = 0
        for kind in _WRITE_ORDER:
            data = parquet_bytes(EXTRACTORS[kind](bag))
            self._store.put_bytes(keys.fleet_file(VERSION, kind, bag.record.id), data)
            written += len(data)
        return written

    def remove(self, bag_id: str) -> None:
        for kind in reversed(_WRITE_ORDER):
            self._store.delete(keys.fleet_file(VERSION, kind, bag_id))

    def read(self, kind: str, bag_id: str) -> pa.Table | None:
        """The bag's rows of ``kind``; None when the file is not stored (yet)."""
        try:
            with self._store.open_read(keys.fleet_file(VERSION, kind, bag_id)) as stream:
                data = stream.read()
        except ObjectNotFoundError:
            return None
        return pq.read_table(pa.BufferReader(data))

    def keys_of(self, bag_id: str) -> Iterator[str]:
        return (keys.fleet_file(VERSION, kind, bag_id) for kind in _WRITE_ORDER)
