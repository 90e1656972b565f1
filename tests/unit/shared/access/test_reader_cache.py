"""The opened-bag cache: readers are reused, bounded by count and bytes, and never shared while in use."""

from __future__ import annotations

from pathlib import Path

import pytest

from bagmcp_shared.access import ReaderCache
from bagmcp_shared.access.readers import reader_bytes
from bagmcp_shared.settings import OpenBagLimits
from tests.fixtures.bagfactory import write_bag


@pytest.fixture(scope="module")
def bags(tmp_path_factory: pytest.TempPathFactory) -> list[Path]:
    directory = tmp_path_factory.mktemp("cache-bags")
    return [write_bag("ros1", directory, name=f"bag{i}") for i in range(3)]


def _count(cache: ReaderCache, bag_id: str, path: Path) -> int:
    with cache.reader(bag_id, path) as reader:
        return sum(1 for _ in reader.messages(["/odom"]))


def test_a_bag_asked_about_twice_is_opened_once(bags: list[Path]) -> None:
    cache = ReaderCache()
    assert _count(cache, "a", bags[0]) == _count(cache, "a", bags[0]) == 200
    assert cache.opened == 1


def test_callers_at_the_same_time_get_readers_of_their_own_which_are_kept_for_later(bags: list[Path]) -> None:
    cache = ReaderCache()
    with cache.reader("a", bags[0]) as first, cache.reader("a", bags[0]) as second:
        assert first is not second
    assert cache.opened == 2
    with cache.reader("a", bags[0]), cache.reader("a", bags[0]):
        pass
    assert cache.opened == 2


def test_the_least_recently_used_bag_is_closed_past_the_count_limit(bags: list[Path]) -> None:
    cache = ReaderCache(OpenBagLimits(max_bags=2))
    for number, path in enumerate(bags):
        _count(cache, f"id{number}", path)
    assert len(cache) == 2
    _count(cache, "id2", bags[2])
    assert cache.opened == 3  # the newest was still cached
    _count(cache, "id0", bags[0])
    assert cache.opened == 4  # the oldest had been closed and is opened again


def test_the_byte_limit_bounds_what_is_kept(bags: list[Path]) -> None:
    with ReaderCache().reader("x", bags[0]) as reader:
        one = reader_bytes(reader)
    cache = ReaderCache(OpenBagLimits(max_bytes=one + 1))
    _count(cache, "id0", bags[0])
    _count(cache, "id1", bags[1])
    assert len(cache) == 1
    assert cache.total_bytes() <= one + 1


def test_discarding_a_bag_and_changing_its_file_both_reopen_it(bags: list[Path]) -> None:
    cache = ReaderCache()
    _count(cache, "a", bags[0])
    cache.discard("a")
    _count(cache, "a", bags[0])
    assert cache.opened == 2
    _count(cache, "a", bags[1])  # same id, another file (the content was stored again elsewhere)
    assert cache.opened == 3
