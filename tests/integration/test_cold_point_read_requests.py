"""A cold point read in team mode makes few S3 requests: a fresh process (empty caches) answering one
``get_message_at_time`` about a stored bag of each format, through a counting loopback proxy in front of a
real weed S3, fetches none of the bag's columnar index files (a point read reads none of them) and opens the
bag in a handful of requests. With 20 ms added to every request on a network object store, each request
costs its 20 ms, since they are made one after the other (issue 21: 19 to 26 requests, 617 to 908 ms)."""

from __future__ import annotations

import threading
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any, BinaryIO, cast

import pytest

from bagmcp_bag_store.ingest.content import content_id
from bagmcp_bag_store.ingest.ingest import Ingestor
from bagmcp_bag_store.ingest.shelf import Shelf
from bagmcp_bag_store.queries.messages import MessageAtTimeParams, get_message_at_time
from bagmcp_bag_store.reports import MessageAtTime
from bagmcp_shared.access import BagAccess, RangedBagFiles
from bagmcp_shared.access.ranged import StoredFile
from bagmcp_shared.access.remote import RemoteStore
from bagmcp_shared.bags.mcap_source import McapSource
from bagmcp_shared.bags.sqlite3_source import forget_topic_stats
from bagmcp_shared.catalog import BagRecord, MemoryCatalog
from bagmcp_shared.settings import RangeReads
from bagmcp_shared.storage import S3Store
from bagmcp_shared.storage.base import RangeAnswer
from bench.delay_proxy import DelayProxy, delay_proxy
from tests.fixtures.bagfactory import BAG_KINDS, BagKind
from tests.fixtures.mcap_cuts import data_section, write_mcap
from tests.fixtures.servers import S3Endpoint
from tests.integration.test_range_reads import s3_of

pytestmark = pytest.mark.integration

# Blocks small enough that the scenario bags (about 0.3 MB) read as a large bag does: header, summary or
# pages, then the chunk asked for, each its own range.
READS = RangeReads(block_bytes=16 << 10, cache_bytes=4 << 20, read_ahead_bytes=64 << 10)
# ROS 1: header, index, chunk; sqlite3: metadata.yaml and the .db3's first block at once, then three pages;
# MCAP: metadata.yaml, the .mcap's first block and its summary at once (the catalog records its size), chunk.
MOST_REQUESTS: dict[BagKind, int] = {"ros1": 3, "ros2-sqlite3": 5, "ros2-mcap": 4}


@pytest.fixture(scope="module")
def proxied(s3_server: S3Endpoint) -> Iterator[tuple[S3Store, S3Store, DelayProxy]]:
    """The bucket seen directly (to store and ingest) and through the counting proxy (to read)."""
    with delay_proxy(s3_server.endpoint) as proxy:
        direct = s3_of(s3_server, f"cold-{proxy.port}")
        direct.ensure_bucket()
        counted = s3_of(S3Endpoint(proxy.endpoint, s3_server.access_key, s3_server.secret_key), direct.bucket)
        counted.ensure_bucket()  # as a service does when it starts (its client learns the bucket's region)
        yield direct, counted, proxy


def stored(store: S3Store, catalog: MemoryCatalog, bag: Path, work: Path) -> BagRecord:
    """``bag`` stored and ingested as the bag-store does (columnar index and fleet views published)."""
    names = sorted(p.name for p in bag.iterdir()) if bag.is_dir() else [bag.name]
    sha = content_id([bag / n for n in names] if bag.is_dir() else [bag], directory=bag.is_dir())
    record, _ = Shelf(catalog, store).register(bag, names, sha, name=bag.name, tags=[])
    files = RangedBagFiles(store, work / "ingest-cache", max_bytes=1 << 30, reads=READS)
    assert Ingestor(catalog, files, files, store).ingest(record.id) == "ready"
    ready = catalog.get(record.id)
    assert ready is not None
    return ready


def requests_of(proxy: DelayProxy, run: Callable[[], object]) -> list[str]:
    """The requests (method, path, range) that went through the proxy while ``run`` ran."""
    before = proxy.counts().requests
    run()
    made = proxy.counts().requests - before
    return list(proxy.recent)[-made:] if made else []


@pytest.mark.parametrize("kind", BAG_KINDS)
def test_a_cold_point_read_fetches_no_index_file_and_makes_few_requests(
    proxied: tuple[S3Store, S3Store, DelayProxy], scenario_bags: dict[BagKind, Path], kind: BagKind, tmp_path: Path
) -> None:
    """Before: the index's 15 files, a HEAD per bag file, then the reads (19, 22 and 22 requests)."""
    direct, counted, proxy = proxied
    catalog = MemoryCatalog()
    record = stored(direct, catalog, scenario_bags[kind], tmp_path)
    assert len(record.index_files) > 5  # the scenario's topics are indexed: columns, fleet views, manifest
    forget_topic_stats()  # as a fresh service process: ingest counted a .db3's rows in this one
    access = BagAccess(catalog, RangedBagFiles(counted, tmp_path / "service", max_bytes=1 << 30, reads=READS))
    params = MessageAtTimeParams(bag=record.name, topic="/odom", time=4.2)
    answers: list[MessageAtTime] = []
    point = requests_of(proxy, lambda: answers.append(get_message_at_time(access, params, budget_bytes=1 << 20)))
    assert answers[0].message.time.offset_s == pytest.approx(4.2, abs=0.05)
    assert not [r for r in point if "/indexes/" in r or r.startswith("HEAD")], point
    assert 2 <= len(point) <= MOST_REQUESTS[kind], point  # at least the bag's start and the chunk read

    def read_odom_column() -> None:
        with access.open(record.name) as bag:
            assert bag.index is not None
            assert len(bag.index.read("/odom", []).t_ns) == bag.topic("/odom").count

    columns = requests_of(proxy, read_odom_column)
    assert sorted(r.rsplit("/", 1)[-1] for r in columns) == ["manifest.json", "odom.npz"]  # what is read, once
    assert requests_of(proxy, read_odom_column) == []


def test_an_mcap_summary_of_many_blocks_is_fetched_in_one_request(
    proxied: tuple[S3Store, S3Store, DelayProxy], tmp_path: Path
) -> None:
    """An MCAP of ~1,080 small chunks has a summary of ~100 KB, seven blocks before the prefetched end: opening
    it reads the section in one ranged GET (the library's record-by-record read of it through the ranged
    file made 3 here: a block, the next, then a read-ahead up to the prefetched end)."""
    direct, counted, proxy = proxied
    path = tmp_path / "many.mcap"
    write_mcap(path, "none", count=3000, chunk_bytes=1000)
    key = f"bags/many-{proxy.port}/many.mcap"
    with path.open("rb") as stream:
        etag = direct.put_stream(key, stream).etag
    size = path.stat().st_size
    summary_start = len(data_section(path))
    assert size - summary_start > 6 * READS.block_bytes  # past the prefetched end block(s)
    files = RangedBagFiles(counted, tmp_path / "service", max_bytes=1 << 30, reads=READS)
    file = files.open_file(StoredFile("many", key, size, etag))
    assert len(requests_of(proxy, file.prefetch_ends)) == 2  # the first block and the end, at once
    opened: list[McapSource] = []
    ranged = cast(BinaryIO, file)
    opening = requests_of(proxy, lambda: opened.append(McapSource(Path("many.mcap"), stream=ranged, size=size)))
    assert [(c.topic, c.count) for c in opened[0].connections] == [("/left", 1500), ("/right", 1500)]
    opened[0].close()
    assert len(opening) == 1, opening


class Rendezvous:
    """An object store (``store``) whose ranged reads wait, up to ``wait_s``, until ``together`` of them have
    arrived, and record which arrived together: reads made at once form one group, a read that waited for
    another's answer starts a group of its own. Which reads share a round trip, without timing anything."""

    def __init__(self, store: S3Store, *, together: int, wait_s: float = 1.0) -> None:
        self._store = store
        self._together = together
        self._wait_s = wait_s
        self._turn = threading.Condition()
        self._open: list[str] | None = None
        self.groups: list[list[str]] = []

    def __getattr__(self, name: str) -> Any:
        return getattr(self._store, name)

    def read_range_tagged(self, key: str, *, offset: int, length: int) -> RangeAnswer:
        with self._turn:
            if self._open is None:
                self._open = []
                self.groups.append(self._open)
            group = self._open
            group.append(f"{key.rsplit('/', 1)[-1]}@{offset}")
            if len(group) < self._together:
                self._turn.wait_for(lambda: self._open is not group, timeout=self._wait_s)
            if self._open is group:
                self._open = None
                self._turn.notify_all()
        return self._store.read_range_tagged(key, offset=offset, length=length)


def test_a_cold_read_of_a_ros2_mcap_directory_fetches_its_summary_with_its_first_block(
    proxied: tuple[S3Store, S3Store, DelayProxy], scenario_bags: dict[BagKind, Path], tmp_path: Path
) -> None:
    """The catalog records each file's size, so a directory's .mcap summary (at the file's end) is fetched at
    once with its first block and metadata.yaml: two round trips for a point read, not three (the summary
    waited for the first block's answer, which told the file's size). A bag recorded before sizes per file
    still answers, in three."""
    direct, _, _ = proxied
    catalog = MemoryCatalog()
    record = stored(direct, catalog, scenario_bags["ros2-mcap"], tmp_path)
    mcap = next(name for name in record.files if name.endswith(".mcap"))
    assert record.file_sizes == {name: (scenario_bags["ros2-mcap"] / name).stat().st_size for name in record.files}
    params = MessageAtTimeParams(bag=record.name, topic="/odom", time=4.2)
    rounds = []
    for label, kept in (("sizes", record), ("older", record.model_copy(update={"file_sizes": {}}))):
        catalog.replace(kept)
        gate = Rendezvous(direct, together=3)
        files = RangedBagFiles(cast(RemoteStore, gate), tmp_path / label, max_bytes=1 << 30, reads=READS)
        answer = get_message_at_time(BagAccess(catalog, files), params, budget_bytes=1 << 20)
        assert answer.message.time.offset_s == pytest.approx(4.2, abs=0.05)
        rounds.append(gate.groups)
    with_sizes, older = rounds
    assert len(with_sizes) == 2, with_sizes
    assert {f"{mcap}@0", "metadata.yaml@0"} < set(with_sizes[0])  # and the summary at the end of the .mcap
    assert len(with_sizes[0]) == 3
    assert len(older) == 3, older
