"""What the bag-store's functions need, bundled once at start-up and passed down."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from bagmcp_bag_store.bagfiles import BagFiles
from bagmcp_bag_store.catalog import Catalog
from bagmcp_shared.storage import ObjectStore

IngestSubmitter = Callable[[str], None]


@dataclass(frozen=True)
class BagStoreDeps:
    """``store`` is the writable object store (None when serving a read-only folder)."""

    catalog: Catalog
    files: BagFiles
    submit_ingest: IngestSubmitter
    store: ObjectStore | None = None
    max_result_bytes: int = 16_000
