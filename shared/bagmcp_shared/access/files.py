"""Local paths of a bag's files and index: straight from a served folder, or from a bounded S3 cache;
and publishing a built index where every process finds it."""

from __future__ import annotations

import fcntl
import os
import shutil
import threading
import time
from collections.abc import Callable, Iterator
from concurrent.futures import ThreadPoolExecutor
from contextlib import contextmanager, suppress
from contextvars import Context, copy_context
from functools import partial
from pathlib import Path
from typing import Protocol, TypeVar

from bagmcp_shared import keys
from bagmcp_shared.access.blocks import BlockCounters
from bagmcp_shared.access.parts import BagPart, local_parts
from bagmcp_shared.bags import BagReader, open_bag
from bagmcp_shared.catalog.models import BagRecord
from bagmcp_shared.errors import StorageError
from bagmcp_shared.fetch_tally import count_fetched
from bagmcp_shared.index.build import MANIFEST
from bagmcp_shared.index.column_index import Locate
from bagmcp_shared.scratch import own_scratch
from bagmcp_shared.storage import LocalStore, ObjectStore

_COMPLETE = ".complete"
# Objects fetched at once for one entry: a bag's columnar index is about fifteen small files, which one by one
# cost a round trip each (15 x 20 ms on a network object store, before a point read can start).
FETCHES_AT_ONCE = 8
T = TypeVar("T")


def at_once(calls: list[Callable[[], T]]) -> list[T]:
    """The results of ``calls``, made at once (up to FETCHES_AT_ONCE threads) when there are several: each is
    a round trip to the object store. Each runs in a copy of the caller's context, so what it fetches counts
    in the caller's fetch tally; the first failure is raised."""
    if len(calls) < 2:
        return [call() for call in calls]
    contexts = [copy_context() for _ in calls]
    with ThreadPoolExecutor(max_workers=min(FETCHES_AT_ONCE, len(calls))) as pool:
        return list(pool.map(Context.run, contexts, calls))


def _base(key: str) -> str:
    """The file name an object is kept under in an entry: the last part of its key."""
    return key.rsplit("/", 1)[-1]


class BagFiles(Protocol):
    def path_for(self, record: BagRecord) -> Path:
        """A local path ``open_bag`` can read: the file, or the ROS 2 bag directory."""
        ...

    def index_dir(self, record: BagRecord) -> Path | None:
        """The local directory of the bag's columnar index, or None when it has none."""
        ...

    def index_locator(self, record: BagRecord) -> Locate | None:
        """How to find each file of the bag's columnar index when it is read, or None when it has none."""
        ...

    def reader_for(self, record: BagRecord) -> tuple[Path, Callable[[], BagReader]]:
        """What the opened-bag cache keys the bag's readers by, and how to open one."""
        ...

    def parts_of(self, record: BagRecord) -> list[BagPart]:
        """The bag's files as parts to stream (a download), without copying them first."""
        ...


class IndexPublisher(Protocol):
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
        self._resolved: dict[str, Path] = {}
        index_root.mkdir(parents=True, exist_ok=True)

    def path_for(self, record: BagRecord) -> Path:
        if record.in_store:
            path = self._store.local_path(record.source)
            return path / record.files[0] if record.layout == "file" else path
        served = self._resolved.get(record.source)
        if served is None:  # resolved once per source: symlinks in the served folder are read-only too
            served = (self._root / record.source).resolve()
            if not served.is_relative_to(self._root):
                raise StorageError(f"bag {record.name} is no longer under the served folder {self._root}")
            self._resolved[record.source] = served
        if not served.exists():
            raise StorageError(f"bag {record.name} is no longer under the served folder {self._root}")
        return served

    def reader_for(self, record: BagRecord) -> tuple[Path, Callable[[], BagReader]]:
        path = self.path_for(record)
        return path, partial(open_bag, path)

    def parts_of(self, record: BagRecord) -> list[BagPart]:
        return local_parts(self.path_for(record))

    def index_dir(self, record: BagRecord) -> Path | None:
        path = self._index_root / record.id
        return path if (path / _COMPLETE).exists() else None

    def index_locator(self, record: BagRecord) -> Locate | None:
        directory = self.index_dir(record)
        return None if directory is None else directory.joinpath

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
    An entry this process checked and marked used less than a quarter of ``min_idle_s`` ago is
    served without the lock (no process evicts it before ``min_idle_s`` of disuse), so repeated
    questions about a bag cost a dictionary lookup and a stat, not a lock and a directory scan.
    The bytes fetched whole are counted in ``counters`` (``whole_bytes``, for /metrics).
    """

    def __init__(
        self,
        store: ObjectStore,
        cache_dir: Path,
        *,
        max_bytes: int,
        min_idle_s: float = 60.0,
        counters: BlockCounters | None = None,
    ) -> None:
        self.counters = counters if counters is not None else BlockCounters()
        self._store = store
        self._dir = cache_dir
        self._max_bytes = max_bytes
        self._min_idle_s = min_idle_s
        self._guard = threading.Lock()
        self._guard_evict = threading.Lock()
        self._locks: dict[str, threading.Lock] = {}
        self._checked: dict[tuple[str, tuple[str, ...]], float] = {}  # entry -> when last checked (monotonic)
        cache_dir.mkdir(parents=True, exist_ok=True)
        self._partials = own_scratch(cache_dir / ".partial")  # on the cache's file system, for the rename

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

    def _ensure(self, name: str, wanted: list[str], *, bag_id: str) -> Path:
        """The complete local copy of the objects ``wanted`` under ``name``, fetched if needed, marked as
        just used (eviction spares entries used within ``min_idle_s``, so the caller can read it now).

        An entry is complete when its marker exists and it holds every wanted file: the same content
        stored again under other file names is fetched again, never read under the old names. The files
        of an entry that are missing are added to it, the others left in place (an index's files are
        fetched one by one as they are read, and a reader may hold one open)."""
        root = self._dir / name
        key = (name, tuple(wanted))
        checked = self._checked.get(key)
        if (
            checked is not None
            and time.monotonic() - checked < self._min_idle_s / 4
            and (root / _COMPLETE).exists()
            and (len(wanted) != 1 or (root / _base(wanted[0])).exists())
        ):
            return root
        with self._locked(name):  # eviction takes the same lock, so it cannot remove the entry meanwhile
            complete = (root / _COMPLETE).exists()
            missing = [k for k in wanted if not (complete and (root / _base(k)).exists())]
            if missing:
                self._fetch_objects(missing, root, into=complete)
            os.utime(root / _COMPLETE)
            self._checked[key] = time.monotonic()
        if missing:  # only a fetch adds bytes
            self._evict(keep={bag_id, f"{bag_id}-index"})
        return root

    def path_for(self, record: BagRecord) -> Path:
        root = self._ensure(record.id, [keys.bag_file(record.id, name) for name in record.files], bag_id=record.id)
        return root / record.files[0] if record.layout == "file" else root

    def reader_for(self, record: BagRecord) -> tuple[Path, Callable[[], BagReader]]:
        path = self.path_for(record)
        return path, partial(open_bag, path)

    def parts_of(self, record: BagRecord) -> list[BagPart]:
        """Streamed from the object store (one HEAD per file for its size), never copied here first."""
        keyed = [(Path(name).name, keys.bag_file(record.id, name)) for name in record.files]
        return [BagPart(name, self._store.stat(key).size, partial(self._store.open_read, key)) for name, key in keyed]

    def has_copy(self, record: BagRecord) -> bool:
        """Whether this cache holds a complete copy of the bag's files now (ingest fetched it here)."""
        root = self._dir / record.id
        return (root / _COMPLETE).exists() and all((root / name).exists() for name in record.files)

    def release_ingested(self, record: BagRecord) -> bool:
        """Called when ingest has read the bag (``record`` as it is now, summary included): a cache whose
        later reads need no whole copy drops it. Here every read needs it, so it stays; returns whether it
        was dropped."""
        return False

    def drop_copy(self, record: BagRecord) -> bool:
        """Remove this cache's whole copy of the bag unless another thread or process is fetching it
        (then it stays, for eviction to take later); returns whether it is gone."""
        entry = self._dir / record.id
        return not entry.exists() or self._try_remove(entry)

    def index_dir(self, record: BagRecord) -> Path | None:
        if not record.index_files:
            return None
        wanted = [keys.index_file(record.id, n) for n in record.index_files]
        return self._ensure(f"{record.id}-index", wanted, bag_id=record.id)

    def index_locator(self, record: BagRecord) -> Locate | None:
        """Each file fetched when first read, into the same entry as ``index_dir``'s: opening the index fetches
        its manifest alone, and a point read none of its files. Fetching all fifteen or so before the first
        question (4.6 of a 2 GB bag's 9.2 MB cold point read, the first of its 19 to 26 requests in sequence)
        cost 0.3 to 0.4 s with 20 ms per request."""
        if MANIFEST not in record.index_files:
            return None
        return partial(self._index_file, record)

    def _index_file(self, record: BagRecord, name: str) -> Path:
        return self._ensure(f"{record.id}-index", [keys.index_file(record.id, name)], bag_id=record.id) / name

    def publish_index(self, record: BagRecord, built: Path) -> list[str]:
        """Every file of the index put at once, up to FETCHES_AT_ONCE (each put is a PUT, or a write and an
        fsync in a local store: one after the other, a short bag's dozen small files cost more than indexing it).
        The record lists them only after every put succeeded (the first failure is raised here)."""
        names = sorted(p.name for p in built.iterdir() if p.is_file())
        at_once([partial(self._store.put_file, keys.index_file(record.id, n), built / n) for n in names])
        return names

    def _fetch_objects(self, wanted: list[str], root: Path, *, into: bool) -> None:
        """Download the objects ``wanted`` into ``root`` (named by their last part), all or nothing: into the
        complete entry ``root`` when ``into`` (each file renamed in), else as a new entry replacing whatever
        is there, whose completion marker is written last, after the rename."""
        scratch = self._partials / f"{root.name}-{threading.get_ident()}"
        shutil.rmtree(scratch, ignore_errors=True)
        scratch.mkdir(parents=True)
        try:
            targets = [scratch / _base(key) for key in wanted]
            at_once(
                [partial(self._store.download_to, key, target) for key, target in zip(wanted, targets, strict=True)]
            )
            fetched = sum(target.stat().st_size for target in targets)
            count_fetched(fetched)
            self.counters.add(whole_bytes=fetched)
            if into:
                for target in targets:
                    target.replace(root / target.name)
            else:
                shutil.rmtree(root, ignore_errors=True)
                scratch.rename(root)
            (root / _COMPLETE).touch()
        finally:
            shutil.rmtree(scratch, ignore_errors=True)

    def _entries(self) -> list[tuple[float, int, Path]]:
        """(last use, bytes, path) of every complete entry."""
        found = []
        for entry in self._dir.iterdir():
            if entry.name.startswith("."):
                continue
            with suppress(FileNotFoundError):
                used = (entry / _COMPLETE).stat().st_mtime
                found.append((used, sum(f.stat().st_size for f in entry.iterdir()), entry))
        return found

    def _evict(self, *, keep: set[str]) -> None:
        """Remove least recently used entries past the limit; never one in ``keep``, one being fetched,
        or one used within ``min_idle_s`` (it may still be open)."""
        with self._guard_evict, (self._dir / ".evict.lock").open("a") as handle:
            fcntl.flock(handle, fcntl.LOCK_EX)
            entries = self._entries()
            total = sum(size for _, size, _ in entries)
            idle_before = time.time() - self._min_idle_s
            for used, size, entry in sorted(entries):
                if total <= self._max_bytes:
                    break
                if entry.name not in keep and used < idle_before and self._try_remove(entry):
                    total -= size

    def _try_remove(self, entry: Path) -> bool:
        with (self._dir / f".lock-{entry.name}").open("a") as handle:
            try:
                fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:
                return False
            shutil.rmtree(entry, ignore_errors=True)
            fcntl.flock(handle, fcntl.LOCK_UN)
        self._checked = {k: v for k, v in self._checked.items() if k[0] != entry.name}
        return True
