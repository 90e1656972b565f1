"""The workers' local cache of bag files: fetched once by content id, bounded, least recently used out."""

from __future__ import annotations

import os
import shutil
import threading
import time
from pathlib import Path

import pytest

from bagmcp_shared.access import CachedBagFiles
from bagmcp_shared.catalog import BagRecord
from bagmcp_shared.errors import ObjectNotFoundError, StorageError
from bagmcp_shared.storage import LocalStore, ObjectInfo
from tests.fixtures.records import stored_record


def _record(store: LocalStore, bag_id: str, size: int) -> BagRecord:
    store.put_bytes(f"bags/{bag_id}/{bag_id}.bag", bytes([len(bag_id)]) * size)
    return stored_record(bag_id, bag_id, size=size)


def test_a_cached_bag_is_fetched_once_and_then_served_locally(tmp_path: Path) -> None:
    store = LocalStore(tmp_path / "objects")
    cache = CachedBagFiles(store, tmp_path / "cache", max_bytes=10_000)
    record = _record(store, "aaaa", 1000)
    first = cache.path_for(record)
    assert first.read_bytes() == bytes([4]) * 1000
    store.delete("bags/aaaa/aaaa.bag")  # the cache must not need the store any more
    assert cache.path_for(record) == first
    assert first.stat().st_size == 1000


def test_the_least_recently_used_bag_is_evicted_past_the_limit(tmp_path: Path) -> None:
    store = LocalStore(tmp_path / "objects")
    cache = CachedBagFiles(store, tmp_path / "cache", max_bytes=2500)
    old, recent, new = (_record(store, name, 1000) for name in ("old", "recent", "newer"))
    cache.path_for(old)
    cache.path_for(recent)
    past = time.time() - 100
    os.utime(tmp_path / "cache" / "old" / ".complete", (past, past))
    cache.path_for(new)
    assert not (tmp_path / "cache" / "old").exists()
    assert (tmp_path / "cache" / "recent" / "recent.bag").exists()
    assert (tmp_path / "cache" / "newer" / "newer.bag").exists()


def test_a_failed_fetch_leaves_no_partial_entry(tmp_path: Path) -> None:
    store = LocalStore(tmp_path / "objects")
    cache = CachedBagFiles(store, tmp_path / "cache", max_bytes=10_000)
    record = _record(store, "gone", 10)
    store.delete("bags/gone/gone.bag")
    with pytest.raises(ObjectNotFoundError, match="gone"):
        cache.path_for(record)
    left = [p.name for p in (tmp_path / "cache").rglob("*") if p.is_file() and not p.name.startswith(".lock-")]
    assert left == []


def test_many_threads_fetching_and_evicting_never_fail_and_stay_near_the_limit(tmp_path: Path) -> None:
    store = LocalStore(tmp_path / "objects")
    records = [_record(store, f"bag{i:02d}", 200) for i in range(40)]
    cache = CachedBagFiles(store, tmp_path / "cache", max_bytes=600, min_idle_s=0)
    errors: list[BaseException] = []

    def worker(offset: int) -> None:
        for step in range(60):
            try:
                cache.path_for(records[(offset * 7 + step) % len(records)])
            except BaseException as err:
                errors.append(err)

    threads = [threading.Thread(target=worker, args=(i,)) for i in range(8)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert errors == []
    entries = [p for p in (tmp_path / "cache").iterdir() if (p / ".complete").exists()]
    assert sum(f.stat().st_size for p in entries for f in p.iterdir()) <= 600 + 8 * 200  # limit + one per thread
    assert not [p for p in (tmp_path / "cache").iterdir() if p.name.startswith(".partial-")]


def test_the_same_content_stored_again_under_another_file_name_is_fetched_again(tmp_path: Path) -> None:
    store = LocalStore(tmp_path / "objects")
    cache = CachedBagFiles(store, tmp_path / "cache", max_bytes=10_000)
    first = _record(store, "same", 100)
    assert cache.path_for(first).name == "same.bag"
    store.delete("bags/same/same.bag")  # deleted, then uploaded again under another name
    store.put_bytes("bags/same/renamed.bag", bytes([4]) * 100)
    again = first.model_copy(update={"files": ["renamed.bag"], "name": "renamed"})
    path = cache.path_for(again)
    assert path.name == "renamed.bag"
    assert path.read_bytes() == bytes([4]) * 100


def test_a_bag_asked_about_again_soon_is_served_without_touching_the_cache_again(tmp_path: Path) -> None:
    store = LocalStore(tmp_path / "objects")
    cache = CachedBagFiles(store, tmp_path / "cache", max_bytes=10_000, min_idle_s=60)
    record = _record(store, "warm", 100)
    first = cache.path_for(record)
    marker = tmp_path / "cache" / "warm" / ".complete"
    past = time.time() - 100
    os.utime(marker, (past, past))
    assert cache.path_for(record) == first
    assert marker.stat().st_mtime == past  # no lock, no touch: checked a moment ago by this process


def test_an_entry_removed_by_another_process_is_fetched_again_at_once(tmp_path: Path) -> None:
    store = LocalStore(tmp_path / "objects")
    cache = CachedBagFiles(store, tmp_path / "cache", max_bytes=10_000, min_idle_s=60)
    record = _record(store, "gone-soon", 100)
    path = cache.path_for(record)
    shutil.rmtree(tmp_path / "cache" / "gone-soon")  # as another process's eviction would
    assert cache.path_for(record) == path
    assert path.read_bytes() == bytes([9]) * 100


class _SlowStore(LocalStore):
    """A local store whose every put takes ``PUT_S`` (a PUT's round trip), failing for names with ``bad``."""

    PUT_S = 0.2

    def put_file(self, key: str, path: Path) -> ObjectInfo:
        time.sleep(self.PUT_S)
        if "bad" in key:
            raise StorageError(f"cannot put {key}")
        return super().put_file(key, path)


def _built(tmp_path: Path, names: list[str]) -> Path:
    built = tmp_path / "built"
    built.mkdir()
    for name in names:
        (built / name).write_bytes(name.encode())
    return built


def test_an_index_is_published_with_its_files_put_at_once(tmp_path: Path) -> None:
    store = _SlowStore(tmp_path / "objects")
    cache = CachedBagFiles(store, tmp_path / "cache", max_bytes=10_000)
    names = [f"fleet.v1.view{n}.parquet" for n in range(8)]
    began = time.monotonic()
    assert cache.publish_index(stored_record("abcd", "abcd", size=1), _built(tmp_path, names)) == sorted(names)
    assert time.monotonic() - began < 4 * _SlowStore.PUT_S  # 8 puts one after the other take 8 times
    for name in names:
        with store.open_read(f"indexes/abcd/columns/{name}") as stored:
            assert stored.read() == name.encode()


def test_a_failed_put_fails_the_publish(tmp_path: Path) -> None:
    cache = CachedBagFiles(_SlowStore(tmp_path / "objects"), tmp_path / "cache", max_bytes=10_000)
    with pytest.raises(StorageError, match=r"bad\.npz"):
        cache.publish_index(stored_record("abcd", "abcd", size=1), _built(tmp_path, ["a.npz", "bad.npz", "c.npz"]))


class _CountingStore(LocalStore):
    """A local store that records the key of every download."""

    def __init__(self, root: Path) -> None:
        super().__init__(root)
        self.downloads: list[str] = []

    def download_to(self, key: str, path: Path) -> None:
        self.downloads.append(key)
        super().download_to(key, path)


def test_an_index_is_fetched_file_by_file_as_it_is_read_and_completed_without_fetching_those_again(
    tmp_path: Path,
) -> None:
    store = _CountingStore(tmp_path / "objects")
    names = ["a.npz", "b.npz", "manifest.json"]
    for name in names:
        store.put_bytes(f"indexes/abcd/columns/{name}", name.encode())
    record = stored_record("abcd", "abcd").model_copy(update={"index_files": names})
    cache = CachedBagFiles(store, tmp_path / "cache", max_bytes=10_000)
    locate = cache.index_locator(record)
    assert locate is not None
    assert locate("manifest.json").read_bytes() == b"manifest.json"
    assert locate("a.npz").read_bytes() == b"a.npz"
    assert locate("a.npz").read_bytes() == b"a.npz"  # once
    assert store.downloads == ["indexes/abcd/columns/manifest.json", "indexes/abcd/columns/a.npz"]
    directory = cache.index_dir(record)  # the whole index, as the fleet views read it: only b.npz is missing
    assert directory is not None
    assert sorted(p.name for p in directory.iterdir() if not p.name.startswith(".")) == names
    assert store.downloads[2:] == ["indexes/abcd/columns/b.npz"]
    assert cache.index_locator(record.model_copy(update={"index_files": ["a.npz"]})) is None  # no manifest
