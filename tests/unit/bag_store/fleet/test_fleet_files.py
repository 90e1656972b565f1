"""The views' files: one Parquet file per view per bag, written at ingest into the bag's index directory (in
the data directory, embedded) and listed with its files, with the views' columns; a ready bag whose index
lacks them is queued at start and gets them added to its index, from the index, without indexing again."""

from __future__ import annotations

import itertools
import shutil
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq
import pytest

from bagmcp_bag_store.fleet.backfill import queue_fleet_backfill
from bagmcp_bag_store.fleet.files import SMALL_ROWS, FleetFiles, file_name, has_views, parquet_bytes
from bagmcp_bag_store.fleet.views import VIEWS
from bagmcp_bag_store.ingest.ingest import Ingestor
from bagmcp_shared.catalog import BagRecord
from tests.fixtures.drive_bags import expected_topic_counts
from tests.fixtures.inprocess import InProcess
from tests.unit.conftest import DRIVE_NAMES

WRITTEN = ["bags", "topics", "poses", "twists", "imu", "gps", "scans", "logs", "tf_edges"]  # the drives have no battery


def _record(served: InProcess, name: str) -> BagRecord:
    record = served.composition.embedded.resources.catalog.named(name)
    assert record is not None
    return record


def test_ingest_writes_each_view_with_rows_into_the_index_with_the_views_columns(served_drive: InProcess) -> None:
    res = served_drive.composition.embedded.resources
    for name in DRIVE_NAMES:
        record = _record(served_drive, name)
        directory = res.files.index_dir(record)
        assert directory is not None
        assert sorted(n for n in record.index_files if n.startswith("fleet.")) == sorted(map(file_name, WRITTEN))
        for kind in WRITTEN:
            assert pq.read_table(directory / file_name(kind)).column_names == VIEWS[kind].names, kind
        files = FleetFiles(res.store, res.files)
        poses, battery = files.read("poses", record), files.read("battery", record)
        assert poses is not None
        assert battery is not None
        assert poses.num_rows == expected_topic_counts("ros1")["/odom"]
        assert set(poses.column("bag").to_pylist()) == {name}
        assert battery.num_rows == 0


def test_every_written_file_is_sorted_by_time_with_its_topics_interleaved(served_drive: InProcess) -> None:
    res = served_drive.composition.embedded.resources
    timed = [k for k in WRITTEN if "t" in VIEWS[k].names]
    assert timed == ["poses", "twists", "imu", "gps", "scans", "logs"]
    for name in DRIVE_NAMES:
        record = _record(served_drive, name)
        directory = res.files.index_dir(record)
        assert directory is not None
        for kind in timed:
            table = pq.read_table(directory / file_name(kind))
            t = table.column("t").to_numpy()
            assert np.all(np.diff(t) >= 0), (name, kind)
            topics = np.asarray(table.column("topic").to_pylist())
            for topic in set(topics):  # each topic's rows keep their order too
                assert np.all(np.diff(table.column("offset_s").to_numpy()[topics == topic]) >= 0), (name, kind, topic)
        twists = pq.read_table(directory / file_name("twists")).column("topic").to_pylist()
        assert set(twists) == {"/odom", "/cmd_vel"}
        switches = sum(a != b for a, b in itertools.pairwise(twists))
        assert switches > 100, (name, switches)  # interleaved by time, not one topic after the other


def test_a_ready_bag_whose_index_lacks_the_views_gets_them_from_its_index(
    served_drive: InProcess, tmp_path: Path
) -> None:
    res = served_drive.composition.embedded.resources
    record = _record(served_drive, "drive_mcap")
    directory = res.files.index_dir(record)
    assert directory is not None
    older = tmp_path / "columns"
    shutil.copytree(directory, older, ignore=shutil.ignore_patterns(".*", "fleet.*"))
    names = res.indexes.publish_index(record, older)
    res.catalog.replace(record.model_copy(update={"index_files": names}))
    assert not has_views(_record(served_drive, "drive_mcap"))
    queued: list[str] = []
    assert queue_fleet_backfill(res.catalog, queued.append) == [record.id]
    assert Ingestor(res.catalog, res.files, res.indexes, res.store).ingest(record.id) == "ready"
    again = _record(served_drive, "drive_mcap")
    assert has_views(again)
    scans = FleetFiles(res.store, res.files).read("scans", again)
    assert scans is not None
    assert scans.num_rows == expected_topic_counts("ros2-mcap")["/scan"]
    assert queue_fleet_backfill(res.catalog, queued.append) == []


def _filled(kind: str, rows: int) -> pa.Table:
    """``rows`` rows of a view, with a NULL number and an empty list among them."""
    values: dict[pa.DataType, Callable[[int], object]] = {
        pa.string(): lambda i: f"text{i % 3}",
        pa.float64(): lambda i: None if i == 1 else i / 7,
        pa.int64(): lambda i: i,
        pa.bool_(): lambda i: i % 2 == 0,
        pa.list_(pa.string()): lambda i: [f"tag{i}"] * (i % 2),
    }
    schema = VIEWS[kind].schema
    return pa.table({f.name: [values[f.type](i) for i in range(rows)] for f in schema}, schema=schema)


@pytest.mark.parametrize("rows", [0, 1, SMALL_ROWS, SMALL_ROWS + 1, 5000])
@pytest.mark.parametrize("kind", ["bags", "poses", "logs", "tf_edges"])
def test_short_tables_written_plain_and_long_ones_compressed_read_back_the_same(kind: str, rows: int) -> None:
    table = _filled(kind, rows)
    encoded = parquet_bytes(table)
    assert pq.read_table(pa.BufferReader(encoded)).equals(table)
    if rows:
        codec = pq.ParquetFile(pa.BufferReader(encoded)).metadata.row_group(0).column(0).compression
        assert codec == ("UNCOMPRESSED" if rows <= SMALL_ROWS else "ZSTD")
