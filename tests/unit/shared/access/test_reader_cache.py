"""The opened-bag cache: readers are reused, bounded by count and bytes, never shared while in use, and closed
with the cache (each test closes the caches it makes: a reader left to the garbage collector warns, an error
in this suite)."""

from __future__ import annotations

import gc
from collections.abc import Callable, Iterator
from pathlib import Path

import pytest

from bagmcp_shared.access import ReaderCache
from bagmcp_shared.access.readers import reader_bytes
from bagmcp_shared.settings import DEFAULT_OPEN_BAGS, OpenBagLimits
from tests.fixtures.bagfactory import write_bag


@pytest.fixture(scope="module")
def bags(tmp_path_factory: pytest.TempPathFactory) -> list[Path]:
    directory = tmp_path_factory.mktemp("cache-bags")
    return [write_bag("ros1", directory, name=f"bag{i}") for i in range(3)]


Caches = Callable[..., ReaderCache]


@pytest.fixture
def caches() -> Iterator[Caches]:
    made: list[ReaderCache] = []

    def make(limits: OpenBagLimits = DEFAULT_OPEN_BAGS) -> ReaderCache:
        made.append(ReaderCache(limits))
        return made[-1]

    yield make
    for cache in made:
        cache.close()


def _count(cache: ReaderCache, bag_id: str, path: Path) -> int:
    with cache.reader(bag_id, path) as reader:
        return sum(1 for _ in reader.messages(["/odom"]))


def test_a_bag_asked_about_twice_is_opened_once(bags: list[Path], caches: Caches) -> None:
    cache = caches()
    assert _count(cache, "a", bags[0]) == _count(cache, "a", bags[0]) == 200
    assert cache.opened == 1


def test_callers_at_the_same_time_get_readers_of_their_own_which_are_kept_for_later(
    bags: list[Path], caches: Caches
) -> None:
    cache = caches()
    with cache.reader("a", bags[0]) as first, cache.reader("a", bags[0]) as second:
        assert first is not second
    assert cache.opened == 2
    with cache.reader("a", bags[0]), cache.reader("a", bags[0]):
        pass
    assert cache.opened == 2


def test_the_least_recently_used_bag_is_closed_past_the_count_limit(bags: list[Path], caches: Caches) -> None:
    cache = caches(OpenBagLimits(max_bags=2))
    for number, path in enumerate(bags):
        _count(cache, f"id{number}", path)
    assert len(cache) == 2
    _count(cache, "id2", bags[2])
    assert cache.opened == 3  # the newest was still cached
    _count(cache, "id0", bags[0])
    assert cache.opened == 4  # the oldest had been closed and is opened again


def test_the_byte_limit_bounds_what_is_kept(bags: list[Path], caches: Caches) -> None:
    with caches().reader("x", bags[0]) as reader:
        one = reader_bytes(reader)
    cache = caches(OpenBagLimits(max_bytes=one + 1))
    _count(cache, "id0", bags[0])
    _count(cache, "id1", bags[1])
    assert len(cache) == 1
    assert cache.total_bytes() <= one + 1


def test_discarding_a_bag_and_changing_its_file_both_reopen_it(bags: list[Path], caches: Caches) -> None:
    cache = caches()
    _count(cache, "a", bags[0])
    cache.discard("a")
    _count(cache, "a", bags[0])
    assert cache.opened == 2
    _count(cache, "a", bags[1])  # same id, another file (the content was stored again elsewhere)
    assert cache.opened == 3


def test_closing_the_cache_closes_its_readers_and_a_busy_one_when_it_is_returned(bags: list[Path]) -> None:
    cache = ReaderCache()
    _count(cache, "a", bags[0])
    with cache.reader("b", bags[1]) as busy:
        cache.close()
        assert len(cache) == 0
        assert sum(1 for _ in busy.messages(["/odom"])) == 200  # still its caller's until returned
    del busy
    gc.collect()  # a reader left open would warn here
    _count(cache, "a", bags[0])
    assert cache.opened == 3
    cache.close()


def test_an_index_that_pushes_a_bag_out_closes_its_readers(bags: list[Path], caches: Caches) -> None:
    cache = caches(OpenBagLimits(max_bags=1))
    assert _count(cache, "a", bags[0]) == 200
    assert cache.index("b", bags[1], lambda: None) is None
    assert len(cache) == 1
    gc.collect()  # the pushed-out reader, had it been dropped unclosed, would warn here
    _count(cache, "a", bags[0])
    assert cache.opened == 2
