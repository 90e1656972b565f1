"""Ingest: read a stored bag once and record what later questions need in the catalog."""

from __future__ import annotations

import json
import logging
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

from bagmcp_bag_store.fleet.extract import IngestedBag
from bagmcp_bag_store.fleet.feeding import ViewFeeder
from bagmcp_shared import keys
from bagmcp_shared.access import BagFiles, CachedBagFiles, IndexPublisher
from bagmcp_shared.bags import BagReader, BagSummary
from bagmcp_shared.catalog import BagRecord, Catalog, CatalogSummary
from bagmcp_shared.errors import BagError, BagNotFoundError
from bagmcp_shared.index import ColumnIndex, build_index
from bagmcp_shared.storage import ObjectStore

log = logging.getLogger(__name__)
PROGRESS_EVERY_S = 0.5


def progress_recorder(catalog: Catalog, bag_id: str, *, start: float, end: float) -> Callable[[float, str], None]:
    """Records a stage's progress (0..1) on the bag as ``start``..``end`` of the whole (list_bags shows
    it while the bag is ingesting), at most twice a second."""
    last = 0.0

    def report(fraction: float, _message: str) -> None:
        nonlocal last
        if time.monotonic() - last < PROGRESS_EVERY_S:
            return
        last = time.monotonic()
        record = catalog.get(bag_id)
        if record is not None and record.status == "ingesting":
            value = start + (end - start) * min(max(fraction, 0.0), 1.0)
            catalog.replace(record.model_copy(update={"progress": round(min(value, 0.99), 3)}))

    return report


def _definitions(bag: BagReader) -> dict[str, dict[str, str]]:
    return {c.msgtype: {"format": c.definition_format, "text": c.definition} for c in bag.connections}


class Ingestor:
    """Summarizes bags into the catalog and builds their columnar index (``store`` keeps a copy of
    what ingest learned next to stored bags, so the catalog can be rebuilt from storage); the index carries
    each bag's rows of the views queries across bags read (fleet/)."""

    def __init__(self, catalog: Catalog, files: BagFiles, indexes: IndexPublisher, store: ObjectStore) -> None:
        self._catalog = catalog
        self._files = files
        self._indexes = indexes
        self._store = store
        self._views = ViewFeeder(catalog, files, indexes)

    def mark_failed(self, bag_id: str, reason: str) -> None:
        """Record why a bag cannot be used (no-op if it was deleted meanwhile)."""
        record = self._catalog.get(bag_id)
        if record is not None:
            self._catalog.replace(record.model_copy(update={"status": "failed", "error": reason, "progress": None}))

    def ingest(self, bag_id: str) -> str:
        """Summarize the bag, build its columnar index, and mark it ready (or failed, with the reason).

        Idempotent: a redelivered task on a ready bag only adds the views' files to its index when they are
        missing (a bag ingested before they existed). Storage errors propagate so the caller can retry; a
        bag deleted while ingesting stays deleted.
        """
        record = self._catalog.get(bag_id)
        if record is None:
            raise BagNotFoundError(f"bag {bag_id} is not in the catalog (deleted while queued?)")
        if record.status == "ready":
            self._views.backfill(record)
            return record.status
        path, opened = self._files.reader_for(record)  # in team mode MCAP and ROS 1 stream by range
        try:
            with opened() as bag:
                found = bag.summary()
                definitions = _definitions(bag)
                index_files, header_rates = self._index(record, bag, found)
        except BagError as err:
            reason = str(err).replace(str(path), record.name)  # no server paths in what clients see
            log.warning("ingest of %s failed: %s", bag_id, reason)
            if isinstance(self._files, CachedBagFiles):  # a bag that failed is never read again
                self._files.drop_copy(record)
            self.mark_failed(bag_id, reason)
            return "failed"
        summary = CatalogSummary.of(found, header_rates=header_rates)
        if record.in_store:
            learned = {"summary": summary.model_dump(mode="json"), "definitions": definitions}
            self._store.put_bytes(keys.ingest_summary(bag_id), json.dumps(learned).encode())
        ready = {"status": "ready", "summary": summary, "error": None, "progress": None, "index_files": index_files}
        done = record.model_copy(update=ready)
        if isinstance(self._files, CachedBagFiles):  # team mode: no whole copy stays once ingest has read it
            self._files.release_ingested(done)
        if not self._catalog.replace(done):
            self._forget_deleted(record, index_files)
            log.info("bag %s was deleted while it was ingested; its index is removed", bag_id)
            return "deleted"
        return "ready"

    def _forget_deleted(self, record: BagRecord, index_files: list[str]) -> None:
        """Remove what this ingest stored for a bag deleted meanwhile (the delete ran before the index and the
        summary existed, so they stayed in storage for good). Safe to repeat: deleting a missing object is a
        no-op."""
        if not record.in_store:
            return
        self._store.delete(keys.ingest_summary(record.id))
        for name in index_files:
            self._store.delete(keys.index_file(record.id, name))

    def _progress(self, record: BagRecord) -> Callable[[float, str], None]:
        """Index building, recorded after whatever share earlier stages (hashing a served file) took."""
        return progress_recorder(self._catalog, record.id, start=record.progress or 0.0, end=1.0)

    def _index(self, record: BagRecord, bag: BagReader, found: BagSummary) -> tuple[list[str], dict[str, float]]:
        """The bag's columnar index with the views' files (reused when this process already has a usable
        one, else built), and the header-stamp rate of each indexed topic that has sane header stamps."""
        directory = self._files.index_dir(record)
        if directory is not None and (existing := ColumnIndex.load(directory)) is not None:
            rates = existing.header_rates()
            summary = CatalogSummary.of(found, header_rates=rates)
            return self._views.reused(record, summary, existing, directory), rates
        with tempfile.TemporaryDirectory(prefix="bagmcp-index-") as tmp:
            build_index(bag, Path(tmp) / "columns", progress=self._progress(record))
            built = ColumnIndex.load(Path(tmp) / "columns")
            assert built is not None
            rates = built.header_rates()
            summary = CatalogSummary.of(found, header_rates=rates)
            self._views.into(Path(tmp) / "columns", IngestedBag(record, summary, built))
            return self._indexes.publish_index(record, Path(tmp) / "columns"), rates
