"""Putting bags on the shelf and taking them off: stored objects and catalog entries together.

A bag is listed only after every object is stored, and a registration next to its files lets the
catalog be rebuilt from storage; removing a bag unlists it first, so it vanishes at once.
"""

from __future__ import annotations

import time
from pathlib import Path

from bagmcp_bag_store.errors import ReadOnlyError
from bagmcp_shared import keys
from bagmcp_shared.catalog import BagRecord, Catalog
from bagmcp_shared.storage import ObjectStore


class Shelf:
    def __init__(self, catalog: Catalog, store: ObjectStore) -> None:
        self._catalog = catalog
        self._store = store

    def register(self, root: Path, files: list[str], sha: str, *, name: str, tags: list[str]) -> tuple[BagRecord, bool]:
        """Store a validated bag's files and list it; returns (record, created). Same content = same bag.

        The catalog entry appears only after every object is stored; a failure removes what was stored.
        """
        bag_id = sha[:16]
        if (existing := self._catalog.get(bag_id)) is not None:
            return existing, False
        self._catalog.claim_name(name, bag_id)
        try:
            etags: dict[str, str] = {}
            sizes: dict[str, int] = {}
            for file in files:
                path = root if root.is_file() else root / file
                etags[file] = self._store.put_file(keys.bag_file(bag_id, file), path).etag
                sizes[file] = path.stat().st_size
            record = BagRecord(
                id=bag_id,
                name=name,
                layout="file" if root.is_file() else "directory",
                files=files,
                source=keys.bag_prefix(bag_id),
                in_store=True,
                sha256=sha,
                size_bytes=sum(sizes.values()),
                created_at=time.time(),
                tags=tags,
                etags={file: etag for file, etag in etags.items() if etag},
                file_sizes=sizes,
            )
            if not self._catalog.add(record):  # the same content was registered concurrently
                self._catalog.release_name(name, bag_id)
                return self._catalog.get(bag_id) or record, False
            self._store.put_bytes(keys.registration(bag_id), record.model_dump_json().encode())
        except BaseException:
            self._catalog.release_name(name, bag_id)
            self._remove_unlisted(bag_id, files)
            raise
        return record, True

    def requeued(self, record: BagRecord) -> BagRecord:
        """The bag marked for another ingest (its ingest failed, or its worker died): the caller queues it."""
        again = record.model_copy(
            update={"status": "ingesting", "error": None, "progress": None, "ingest_queued_at": time.time()}
        )
        self._catalog.replace(again)
        return again

    def remove(self, record: BagRecord) -> None:
        """Remove a bag's catalog entry, objects and index with its views' files (catalog first, so it
        vanishes at once)."""
        if not record.in_store:
            raise ReadOnlyError(f"bag {record.name} is part of the served folder; remove it there, not through bagmcp")
        self._catalog.delete(record.id)
        self._store.delete(keys.registration(record.id))
        for name in record.files:
            self._store.delete(keys.bag_file(record.id, name))
        self._store.delete(keys.ingest_summary(record.id))
        for name in record.index_files:
            self._store.delete(keys.index_file(record.id, name))

    def _remove_unlisted(self, bag_id: str, files: list[str]) -> None:
        """After a failed registration, remove its objects unless another registration of the same
        content (same keys) got listed meanwhile."""
        if self._catalog.get(bag_id) is None:
            for name in files:
                self._store.delete(keys.bag_file(bag_id, name))
