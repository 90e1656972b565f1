"""Local paths of a bag's files: straight from a served folder, or from a bounded S3 cache."""

from __future__ import annotations

import os
import shutil
import threading
from pathlib import Path
from typing import Protocol

from bagmcp_bag_store.models import BagRecord
from bagmcp_shared.errors import StorageError
from bagmcp_shared.storage import ObjectStore

_COMPLETE = ".complete"


class BagFiles(Protocol):
    def path_for(self, record: BagRecord) -> Path:
        """A local path ``open_bag`` can read: the file, or the ROS 2 bag directory."""
        ...


class FolderBagFiles:
    """Embedded mode: bags are files and directories under one served folder."""

    def __init__(self, root: Path) -> None:
        self._root = root.resolve()

    def path_for(self, record: BagRecord) -> Path:
        path = (self._root / record.source).resolve()
        if not path.is_relative_to(self._root) or not path.exists():
            raise StorageError(f"bag {record.name} is no longer under the served folder {self._root}")
        return path


class CachedBagFiles:
    """Team mode: bag files live in the object store; workers keep a bounded local cache by id."""

    def __init__(self, store: ObjectStore, cache_dir: Path, *, max_bytes: int) -> None:
        self._store = store
        self._dir = cache_dir
        self._max_bytes = max_bytes
        self._lock = threading.Lock()
        cache_dir.mkdir(parents=True, exist_ok=True)

    def _local(self, record: BagRecord, root: Path) -> Path:
        return root / record.files[0] if record.layout == "file" else root

    def path_for(self, record: BagRecord) -> Path:
        root = self._dir / record.id
        with self._lock:
            if (root / _COMPLETE).exists():
                os.utime(root / _COMPLETE)
                return self._local(record, root)
            self._fetch(record, root)
            self._evict(keep=record.id)
        return self._local(record, root)

    def _fetch(self, record: BagRecord, root: Path) -> None:
        partial = self._dir / f".partial-{record.id}-{os.getpid()}-{threading.get_ident()}"
        shutil.rmtree(partial, ignore_errors=True)
        partial.mkdir(parents=True)
        try:
            for name in record.files:
                self._store.download_to(f"{record.source}/{name}", partial / name)
            (partial / _COMPLETE).touch()
            shutil.rmtree(root, ignore_errors=True)
            partial.rename(root)
        finally:
            shutil.rmtree(partial, ignore_errors=True)

    def _evict(self, *, keep: str) -> None:
        entries = []
        for entry in self._dir.iterdir():
            marker = entry / _COMPLETE
            if entry.name != keep and marker.exists():
                size = sum(f.stat().st_size for f in entry.iterdir())
                entries.append((marker.stat().st_mtime, size, entry))
        total = sum(size for _, size, _ in entries) + sum(
            f.stat().st_size for f in (self._dir / keep).iterdir()
        )
        for _, size, entry in sorted(entries):
            if total <= self._max_bytes:
                break
            shutil.rmtree(entry, ignore_errors=True)
            total -= size

    def forget(self, bag_id: str) -> None:
        shutil.rmtree(self._dir / bag_id, ignore_errors=True)
