"""The columnar store's files: one Parquet file per view per bag (``fleet.v1.<view>.parquet``), written at
ingest into the bag's index directory and published with it, so they live next to the index: in the object
store in team mode (``indexes/<id>/columns/``), in the data directory when embedded. The catalog record lists
them with the index's files, so deleting a bag removes them and a catalog rebuilt from storage finds them.

Why Parquet (pyarrow): it is what DuckDB, Trino, Spark, Polars and MotherDuck all read in place, so the same
files serve ``query_bags`` on one machine and a distributed engine past it; pyarrow writes them from the
index's numpy arrays, and zstd keeps a short bag's files to a few KB each. The index's own ``.npz`` files stay
for the per-bag hot paths (see README: loading one topic's columns from .npz is a plain array read).

Writing into the index directory rather than as objects of their own matters for ingest time: each object
store write is a fsync (local store) or a PUT, 5-15 ms each, which for a short bag cost as much as indexing it;
inside the index directory the files cost their encoding (about 2 ms each) and travel with the index.

Files are read through the project's object store (one GET of a whole small file) or, embedded, from the
local index directory: not through DuckDB's httpfs (an extension downloaded at run time, with no network
here) nor pyarrow's own S3 filesystem (it would need the S3 settings, CA file and timeouts configured a
second time, beside the store's). The ``bags`` file is written last: a bag whose index lists it has all its
views, and a view it has no file of has no rows (empty views are not written).
"""

from __future__ import annotations

import io
from pathlib import Path

import pyarrow as pa
import pyarrow.parquet as pq

from bagmcp_bag_store.fleet.extract import EXTRACTORS, IngestedBag
from bagmcp_bag_store.fleet.views import KINDS, VERSION, VIEWS
from bagmcp_shared import keys
from bagmcp_shared.access import BagFiles
from bagmcp_shared.catalog import BagRecord
from bagmcp_shared.errors import ObjectNotFoundError
from bagmcp_shared.storage import ObjectStore

MARKER = "bags"
_WRITE_ORDER = [k for k in KINDS if k != MARKER] + [MARKER]


def file_name(kind: str) -> str:
    return f"fleet.{VERSION}.{kind}.parquet"


def has_views(record: BagRecord) -> bool:
    """Whether the bag's index holds every view's file."""
    return file_name(MARKER) in record.index_files


SMALL_ROWS = 32  # a table this short is written plain: a smaller file, encoded in 0.3 ms instead of 0.5


def parquet_bytes(table: pa.Table) -> bytes:
    """``table`` as a Parquet file: zstd, dictionaries for text columns only (bag, topic and level names
    repeat; numbers rarely do), row groups of 64k rows with statistics, so readers can skip by time. Encoded
    in memory: pyarrow opening a local file for the writer took 14 ms a file under load, a plain write 1 ms.
    A table of at most ``SMALL_ROWS`` rows (a bag's row, a short bag's topics, logs or TF edges) has nothing
    to gain from compression, dictionaries or statistics: its file is written without them (2.2 KB instead
    of 3.5 KB for a one-row logs table)."""
    sink = io.BytesIO()
    if table.num_rows <= SMALL_ROWS:
        pq.write_table(table, sink, compression="none", use_dictionary=False, write_statistics=False)
        return sink.getvalue()
    text = [f.name for f in table.schema if pa.types.is_string(f.type)]
    pq.write_table(table, sink, compression="zstd", row_group_size=65_536, use_dictionary=text)
    return sink.getvalue()


def write_views(bag: IngestedBag, directory: Path) -> list[str]:
    """Write the bag's file of every view that has rows into ``directory`` (the marker last, always)."""
    written = []
    for kind in _WRITE_ORDER:
        table = EXTRACTORS[kind](bag)
        if table.num_rows or kind == MARKER:
            (directory / file_name(kind)).write_bytes(parquet_bytes(table))
            written.append(file_name(kind))
    return written


class FleetFiles:
    """Reads the views' files of ingested bags: from the object store, else from the local index directory
    (an embedded server keeps indexes in its data directory, outside the store)."""

    def __init__(self, store: ObjectStore, files: BagFiles) -> None:
        self._store = store
        self._files = files

    def read(self, kind: str, record: BagRecord) -> pa.Table | None:
        """The bag's rows of ``kind``; None when its views are not written (yet)."""
        if not has_views(record):
            return None
        name = file_name(kind)
        if name not in record.index_files:
            return VIEWS[kind].empty
        try:
            with self._store.open_read(keys.index_file(record.id, name)) as stream:
                return pq.read_table(pa.BufferReader(stream.read()))
        except ObjectNotFoundError:
            directory = self._files.index_dir(record)
            if directory is None or not (directory / name).is_file():
                return None
            return pq.read_table(directory / name)
