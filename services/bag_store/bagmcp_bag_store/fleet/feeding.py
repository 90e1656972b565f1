"""Feeding the columnar store at ingest: the views' files written into a bag's index directory before it is
published (a new index), or added to an index published before they existed (the index of a bag ingested
earlier, found again at start: its files are copied beside the new ones and the whole is published again)."""

from __future__ import annotations

import logging
import shutil
import tempfile
from pathlib import Path

from bagmcp_bag_store.fleet.extract import IngestedBag
from bagmcp_bag_store.fleet.files import has_views, write_views
from bagmcp_shared.access import BagFiles, IndexPublisher
from bagmcp_shared.catalog import BagRecord, Catalog, CatalogSummary
from bagmcp_shared.errors import BagmcpError
from bagmcp_shared.index import ColumnIndex

log = logging.getLogger(__name__)


def index_names(directory: Path) -> list[str]:
    """The files of a published index directory (not its hidden markers)."""
    return sorted(p.name for p in directory.iterdir() if p.is_file() and not p.name.startswith("."))


class ViewFeeder:
    def __init__(self, catalog: Catalog, files: BagFiles, indexes: IndexPublisher) -> None:
        self._catalog = catalog
        self._files = files
        self._indexes = indexes

    def into(self, directory: Path, bag: IngestedBag) -> bool:
        """Write the views' files into an index directory about to be published; False when they could not
        be made (logged: the bag stays usable and its views are made again at the next start)."""
        try:
            write_views(bag, directory)
        except (BagmcpError, ValueError, TypeError, OSError) as err:
            log.exception("the views of bag %s could not be written: %s", bag.record.id, err)
            return False
        return True

    def added(self, bag: IngestedBag, directory: Path) -> list[str] | None:
        """Publish the index in ``directory`` again with the views' files; its file names, or None when the
        views could not be made."""
        with tempfile.TemporaryDirectory(prefix="bagmcp-views-") as tmp:
            again = Path(tmp) / "columns"
            shutil.copytree(directory, again, ignore=shutil.ignore_patterns(".*"))
            if not self.into(again, bag):
                return None
            return self._indexes.publish_index(bag.record, again)

    def backfill(self, record: BagRecord) -> None:
        """Add the views to a ready bag's published index when it lacks them (recorded in the catalog)."""
        if has_views(record) or record.summary is None:
            return
        directory = self._files.index_dir(record)
        index = ColumnIndex.load(directory)
        if directory is None or index is None:
            return
        names = self.added(IngestedBag(record, record.summary, index), directory)
        if names is not None:
            self._catalog.replace(record.model_copy(update={"index_files": names}))

    def reused(self, record: BagRecord, summary: CatalogSummary, index: ColumnIndex, directory: Path) -> list[str]:
        """The file names of an index this process reuses, with the views added when it lacks them."""
        names = record.index_files or index_names(directory)
        if has_views(record.model_copy(update={"index_files": names})):
            return names
        return self.added(IngestedBag(record, summary, index), directory) or names
