"""Local paths of a bag's files: straight from a served folder, or from a bounded S3 cache."""

from __future__ import annotations

import fcntl
import os
import shutil
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Protocol

from bagmcp_bag_store.models import BagRecord
from bagmcp_shared.errors import StorageError
from bagmcp_shared.storage import LocalStore, ObjectStore

_COMPLETE = ".complete"


class BagFiles(Protocol):
    def path_for(self, record: BagRecord) -> Path:
        """A local path ``open_bag`` can read: the file, or the ROS 2 bag directory."""
        ...

    def index_dir(self, record: BagRecord) -> Path | None:
        """The local directory of the bag's columnar index, or None when it has none."""
        ...

    def publish_index(self, record: BagRecord, built: Path) -> list[str]:
        """Make an index built in ``built`` available to every process; returns its file names."""
        ...


class FolderBagFiles:
    """Embedded mode: bags under one served folder (never written to), bags the server made itself
    (filter_bag) in a local store, and indexes in a writable directory."""

    def __init__(self, root: Path, index_root: Path, store: LocalStore) -> None:
        self._root = root.resolve()
        self._index_root = index_root
        self._store = store
        index_root.mkdir(parents=True, exist_ok=True)

    def path_for(self, record: BagRecord) -> Path:
        if record.in_store:
            path = self._store.local_path(record.source)
            return path / record.files[0] if record.layout == "file" else path
        path = (self._root / record.source).resolve()
        if not path.is_relative_to(self._root) or not path.exists():
            raise StorageError(f"bag {record.name} is no longer under the served folder {self._root}")
        return path

    def index_dir(self, record: BagRecord) -> Path | None:
        path = self._index_root / record.id
        return path if (path / _COMPLETE).exists() else None

    def publish_index(self, record: BagRecord, built: Path) -> list[str]:
        target = self._index_root / record.id
        (built / _COMPLETE).touch()
        shutil.rmtree(target, ignore_errors=True)
        shutil.move(built, target)
        return sorted(p.name for p in target.iterdir() if p.name != _COMPLETE)


class CachedBagFiles:
    """Team mode: bag files live in the object store; each process keeps a bounded local cache by id.

    Fetches of one bag are serialized across threads and processes (a lock file per entry), so
    two workers never download the same bag at once and eviction skips entries being fetched.
    """

    def __init__(self, store: ObjectStore, cache_dir: Path, *, max_bytes: int) -> None:
        self._store = store
        self._dir = cache_dir
        self._max_bytes = max_bytes
        self._guard = threading.Lock()
        self._locks: dict[str, threading.Lock] = {}
        cache_dir.mkdir(parents=True, exist_ok=True)

    @contextmanager
    def _locked(self, name: str) -> Iterator[None]:
        with self._guard:
            lock = self._locks.setdefault(name, threading.Lock())
        with lock, (self._dir / f".lock-{name}").open("a") as handle:
            fcntl.flock(handle, fcntl.LOCK_EX)
            try:
                yield
            finally:
                fcntl.flock(handle, fcntl.LOCK_UN)

    def _ensure(self, name: str, keys: list[str]) -> Path:
        root = self._dir / name
        if not (root / _COMPLETE).exists():
            with self._locked(name):
                if not (root / _COMPLETE).exists():
                    self._fetch_objects(keys, root)
            self._evict(keep=name)
        os.utime(root / _COMPLETE)
        return root

    def path_for(self, record: BagRecord) -> Path:
        root = self._ensure(record.id, [f"{record.source}/{name}" for name in record.files])
        return root / record.files[0] if record.layout == "file" else root

    def index_dir(self, record: BagRecord) -> Path | None:
        if not record.index_files:
            return None
        keys = [f"indexes/{record.id}/columns/{n}" for n in record.index_files]
        return self._ensure(f"{record.id}-index", keys)

    def publish_index(self, record: BagRecord, built: Path) -> list[str]:
        names = sorted(p.name for p in built.iterdir() if p.is_file())
        for name in names:
            self._store.put_file(f"indexes/{record.id}/columns/{name}", built / name)
        return names

    def _fetch_objects(self, keys: list[str], root: Path) -> None:
        """Download ``keys`` into ``root`` (named by their last part), all or nothing."""
        partial = self._dir / f".partial-{root.name}-{os.getpid()}-{threading.get_ident()}"
        shutil.rmtree(partial, ignore_errors=True)
        partial.mkdir(parents=True)
        try:
            for key in keys:
                self._store.download_to(key, partial / key.rsplit("/", 1)[-1])
            (partial / _COMPLETE).touch()
            shutil.rmtree(root, ignore_errors=True)
            partial.rename(root)
        finally:
            shutil.rmtree(partial, ignore_errors=True)

    def _evict(self, *, keep: str) -> None:
        """Remove least recently used entries (never ``keep``, never one being fetched) past the limit."""
        entries = []
        for entry in self._dir.iterdir():
            marker = entry / _COMPLETE
            if marker.exists():
                size = sum(f.stat().st_size for f in entry.iterdir())
                entries.append((marker.stat().st_mtime, size, entry))
        total = sum(size for _, size, _ in entries)
        for _, size, entry in sorted(entries):
            if total <= self._max_bytes:
                break
            if entry.name != keep and self._try_remove(entry):
                total -= size

    def _try_remove(self, entry: Path) -> bool:
        with (self._dir / f".lock-{entry.name}").open("a") as handle:
            try:
                fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:
                return False
            shutil.rmtree(entry, ignore_errors=True)
            fcntl.flock(handle, fcntl.LOCK_UN)
        return True
