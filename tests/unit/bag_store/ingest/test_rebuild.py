"""The catalog rebuilt from storage alone: the same ids, names, tags, summaries and indexes as before."""

from __future__ import annotations

from pathlib import Path

import pytest

from bagmcp_bag_store.ingest.content import content_id
from bagmcp_bag_store.ingest.ingest import Ingestor
from bagmcp_bag_store.ingest.rebuild import rebuild_catalog, restore_lost_catalog
from bagmcp_bag_store.ingest.shelf import Shelf
from bagmcp_shared import keys
from bagmcp_shared.access import CachedBagFiles
from bagmcp_shared.catalog import BagRecord, MemoryCatalog
from bagmcp_shared.storage import LocalStore
from tests.fixtures.bagfactory import BagKind


def _shelve(shelf: Shelf, bag: Path, name: str) -> BagRecord:
    files = [bag] if bag.is_file() else sorted(bag.iterdir())
    sha = content_id(files, directory=bag.is_dir())
    record, created = shelf.register(bag, [f.name for f in files], sha, name=name, tags=["run:7"])
    assert created
    return record


@pytest.fixture
def store(tmp_path: Path) -> LocalStore:
    return LocalStore(tmp_path / "objects")


def test_ingested_bags_come_back_ready_and_the_others_to_be_ingested(
    store: LocalStore, scenario_bags: dict[BagKind, Path], tmp_path: Path
) -> None:
    catalog = MemoryCatalog()
    files = CachedBagFiles(store, tmp_path / "cache", max_bytes=1 << 30)
    shelf = Shelf(catalog, store)
    ingested = _shelve(shelf, scenario_bags["ros2-mcap"], "drive")
    assert Ingestor(catalog, files, files, store).ingest(ingested.id) == "ready"
    waiting = _shelve(shelf, scenario_bags["ros1"], "waiting")
    before = {r.id: r for r in catalog.all()}

    lost = MemoryCatalog()
    rebuilt = rebuild_catalog(lost, store)
    assert (rebuilt.ready, rebuilt.to_ingest, rebuilt.skipped) == ([ingested.id], [waiting.id], [])
    again = lost.get(ingested.id)
    assert again is not None
    assert again.model_dump(exclude={"ingest_queued_at"}) == before[ingested.id].model_dump(
        exclude={"ingest_queued_at"}
    )
    assert again.index_files  # the columnar index is found again
    queued = lost.get(waiting.id)
    assert queued is not None
    assert (queued.name, queued.status, queued.tags) == ("waiting", "ingesting", ["run:7"])
    assert rebuild_catalog(lost, store).ready == []  # a second run lists nothing twice


def test_a_registration_without_its_files_is_skipped_and_a_taken_name_gets_the_ids_start(
    store: LocalStore, scenario_bags: dict[BagKind, Path]
) -> None:
    shelf = Shelf(MemoryCatalog(), store)
    half_deleted = _shelve(shelf, scenario_bags["ros1"], "half")
    store.delete(keys.bag_file(half_deleted.id, half_deleted.files[0]))
    named = _shelve(shelf, scenario_bags["ros2-sqlite3"], "taken")
    lost = MemoryCatalog()
    lost.claim_name("taken", "someone-else")
    rebuilt = rebuild_catalog(lost, store)
    assert rebuilt.skipped == [
        f"catalog/{half_deleted.id}.json: its files {half_deleted.files[0]} are missing from storage"
    ]
    record = lost.get(named.id)
    assert record is not None
    assert record.name == f"taken-{named.id[:8]}"


def test_only_an_empty_catalog_over_a_store_with_bags_is_restored_at_start(
    store: LocalStore, scenario_bags: dict[BagKind, Path]
) -> None:
    queued: list[str] = []
    assert restore_lost_catalog(MemoryCatalog(), store, queued.append) is None  # nothing stored
    record = _shelve(Shelf(MemoryCatalog(), store), scenario_bags["ros1"], "kept")
    kept = MemoryCatalog()
    kept.add(record)
    assert restore_lost_catalog(kept, store, queued.append) is None  # not lost
    lost = MemoryCatalog()
    restored = restore_lost_catalog(lost, store, queued.append)
    assert restored is not None
    assert restored.to_ingest == [record.id]
    assert queued == [record.id]
    listed = lost.get(record.id)
    assert listed is not None
    assert (listed.name, listed.files) == ("kept", record.files)
