"""A bag deleted while it is ingested leaves nothing in storage: the delete ran before its columnar index and
ingest summary existed, and the ingest stored them after it (they stayed for good). Real stores and a real
ingest; the delete runs through the shelf at the ingest's first progress report."""

from __future__ import annotations

from pathlib import Path

from bagmcp_bag_store.ingest.content import content_id
from bagmcp_bag_store.ingest.ingest import Ingestor
from bagmcp_bag_store.ingest.shelf import Shelf
from bagmcp_shared.access import CachedBagFiles
from bagmcp_shared.catalog import BagRecord, MemoryCatalog
from bagmcp_shared.storage import LocalStore
from tests.fixtures.bagfactory import BagKind


class DeletedAtFirstProgress(MemoryCatalog):
    """A catalog whose bag is deleted (through ``shelf``) when ingest first reports progress on it."""

    shelf: Shelf | None = None

    def replace(self, record: BagRecord) -> bool:
        if record.progress is not None and self.shelf is not None and self.get(record.id) is not None:
            shelf, self.shelf = self.shelf, None
            shelf.remove(self.get(record.id) or record)
            return False
        return super().replace(record)


def test_a_bag_deleted_during_its_ingest_leaves_no_index_in_storage(
    tmp_path: Path, scenario_bags: dict[BagKind, Path]
) -> None:
    store = LocalStore(tmp_path / "objects")
    catalog = DeletedAtFirstProgress()
    files = CachedBagFiles(store, tmp_path / "cache", max_bytes=1 << 30)
    shelf = Shelf(catalog, store)
    bag = scenario_bags["ros2-mcap"]
    bag_files = sorted(bag.iterdir())
    record, _ = shelf.register(
        bag, [f.name for f in bag_files], content_id(bag_files, directory=True), name="gone", tags=[]
    )
    catalog.shelf = shelf
    assert Ingestor(catalog, files, files, store).ingest(record.id) == "deleted"
    assert catalog.get(record.id) is None
    assert [info.key for info in store.list("") if record.id in info.key] == []
