"""The columnar store's files: one Parquet file per view per bag, written at ingest in the data directory's
store (embedded), with the views' columns; a ready bag missing them is queued at start and gets them back
from its index without a new index."""

from __future__ import annotations

import pyarrow.parquet as pq

from bagmcp_bag_store.fleet.backfill import queue_fleet_backfill
from bagmcp_bag_store.fleet.files import FleetFiles
from bagmcp_bag_store.fleet.views import KINDS, VERSION, VIEWS
from bagmcp_bag_store.ingest.ingest import Ingestor
from bagmcp_shared import keys
from bagmcp_shared.storage import LocalStore
from tests.fixtures.drive_bags import expected_topic_counts
from tests.fixtures.inprocess import InProcess
from tests.unit.conftest import DRIVE_NAMES


def test_ingest_writes_every_view_of_every_bag_with_the_views_columns(served_drive: InProcess) -> None:
    res = served_drive.composition.embedded.resources
    assert isinstance(res.store, LocalStore)
    for name in DRIVE_NAMES:
        record = res.catalog.named(name)
        assert record is not None
        for kind in KINDS:
            path = res.store.local_path(keys.fleet_file(VERSION, kind, record.id))
            table = pq.read_table(path)
            assert table.column_names == VIEWS[kind].names, kind
        poses = pq.read_table(res.store.local_path(keys.fleet_file(VERSION, "poses", record.id)))
        assert poses.num_rows == expected_topic_counts("ros1")["/odom"]
        assert set(poses.column("bag").to_pylist()) == {name}


def test_a_ready_bag_without_its_files_is_queued_at_start_and_fed_from_its_index(served_drive: InProcess) -> None:
    res = served_drive.composition.embedded.resources
    files = FleetFiles(res.store)
    record = res.catalog.named("drive_mcap")
    assert record is not None
    for key in files.keys_of(record.id):
        res.store.delete(key)
    assert not files.complete(record.id)
    queued: list[str] = []
    assert queue_fleet_backfill(res.catalog, res.store, queued.append) == [record.id]
    assert queued == [record.id]
    assert Ingestor(res.catalog, res.files, res.indexes, res.store).ingest(record.id) == "ready"
    assert files.complete(record.id)
    scans = files.read("scans", record.id)
    assert scans is not None
    assert scans.num_rows == expected_topic_counts("ros2-mcap")["/scan"]
    assert queue_fleet_backfill(res.catalog, res.store, queued.append) == []
