"""Team mode reads MCAP bags where they are stored: byte ranges from a real weed S3 through the block
cache on disk, checked against the same bag read from its local file (the embedded answers)."""

from __future__ import annotations

import hashlib
import json
import random
import secrets
import shutil
import sqlite3
from collections.abc import Iterator
from concurrent.futures import ProcessPoolExecutor
from contextlib import ExitStack, closing
from dataclasses import replace
from multiprocessing import get_context
from pathlib import Path
from typing import cast

import pytest
import yaml
from mcap.writer import CompressionType, Writer
from rosbags.rosbag1 import Writer as Ros1Writer
from rosbags.rosbag2 import CompressionMode, StoragePlugin
from rosbags.rosbag2 import Writer as Ros2Writer
from rosbags.typesys import Stores, get_typestore

from bagmcp_bag_store.ingest.content import content_id
from bagmcp_bag_store.ingest.ingest import Ingestor
from bagmcp_bag_store.ingest.shelf import Shelf
from bagmcp_shared import keys
from bagmcp_shared.access import BagAccess, RangedBagFiles
from bagmcp_shared.bags import BagReader, BagSummary, open_bag
from bagmcp_shared.bags.sqlite3_source import forget_topic_stats
from bagmcp_shared.catalog import BagRecord, MemoryCatalog
from bagmcp_shared.errors import DamagedBagError, StorageError
from bagmcp_shared.settings import RangeReads
from bagmcp_shared.storage import S3Store
from tests.fixtures.compressed_bags import CompressedKind, write_compressed, write_ros2_compressed
from tests.fixtures.faults import weed_server
from tests.fixtures.restartable import Restartable
from tests.fixtures.servers import S3Endpoint, remove_weed_sockets

pytestmark = pytest.mark.integration

COUNT = 3000
START_NS = 1_700_000_000_000_000_000
PERIOD_NS = 10_000_000  # 100 Hz: 30 s
SMALL = RangeReads(block_bytes=16 * 1024, cache_bytes=256 * 1024, read_ahead_bytes=32 * 1024)
ROOMY = RangeReads(block_bytes=64 * 1024, cache_bytes=64 * 2**20, read_ahead_bytes=256 * 1024)
Answer = list[tuple[str, int, bytes]]


def write_padded_mcap(path: Path, *, seed: int = 21) -> Path:
    """COUNT JSON poses on /pose and every tenth one on /status, each pose with ~1 KB of random padding,
    in uncompressed 64 KiB chunks: about 3.2 MB in some 50 chunks, so a point read needs few of them."""
    rng = random.Random(seed)
    with path.open("wb") as stream:
        writer = Writer(stream, compression=CompressionType.NONE, chunk_size=64 * 1024)
        writer.start(profile="", library="bagmcp-tests")
        schema = writer.register_schema("robot.Pose", "jsonschema", json.dumps({"type": "object"}).encode())
        pose = writer.register_channel("/pose", "json", schema)
        status = writer.register_channel("/status", "json", schema)
        for i in range(COUNT):
            t = START_NS + i * PERIOD_NS
            body = {"seq": i, "x": i / 100, "pad": rng.randbytes(512).hex()}
            writer.add_message(pose, t, json.dumps(body).encode(), t)
            if i % 10 == 0:
                writer.add_message(status, t, json.dumps({"seq": i, "mode": "auto"}).encode(), t)
        writer.finish()  # type: ignore[no-untyped-call]
    return path


def write_padded_ros1(path: Path, compression: str, *, seed: int = 21) -> Path:
    """The same poses as std_msgs/String in a ROS 1 bag of 64 KiB chunks (plain, bz2 or lz4)."""
    rng = random.Random(seed)
    store = get_typestore(Stores.ROS1_NOETIC)
    string = store.types["std_msgs/msg/String"]
    writer = Ros1Writer(path)
    if compression != "none":
        writer.set_compression(Ros1Writer.CompressionFormat[compression.upper()])
    writer.chunk_threshold = 64 * 1024
    with writer:
        pose = writer.add_connection("/pose", "std_msgs/msg/String", typestore=store)
        status = writer.add_connection("/status", "std_msgs/msg/String", typestore=store)
        for i in range(COUNT):
            t = START_NS + i * PERIOD_NS
            body = json.dumps({"seq": i, "x": i / 100, "pad": rng.randbytes(512).hex()})
            writer.write(pose, t, store.serialize_ros1(string(data=body), "std_msgs/msg/String"))
            if i % 10 == 0:
                status_body = json.dumps({"seq": i, "mode": "auto"})
                writer.write(status, t, store.serialize_ros1(string(data=status_body), "std_msgs/msg/String"))
    return path


def write_padded_db3(directory: Path, *, seed: int = 21, count: int = COUNT, first: int = 0) -> Path:
    """The same poses as std_msgs/String in a ROS 2 sqlite3 directory (one .db3 and metadata.yaml): about
    3.7 MB in 4 KiB pages, its timestamp index beside the rows (poses ``first`` .. ``first + count``)."""
    rng = random.Random(seed)
    store = get_typestore(Stores.ROS2_HUMBLE)
    typename = "std_msgs/msg/String"
    string = store.types[typename]
    with Ros2Writer(directory, version=9, storage_plugin=StoragePlugin.SQLITE3) as writer:
        pose = writer.add_connection("/pose", typename, typestore=store)
        status = writer.add_connection("/status", typename, typestore=store)
        for i in range(first, first + count):
            t = START_NS + i * PERIOD_NS
            body = json.dumps({"seq": i, "x": i / 100, "pad": rng.randbytes(512).hex()})
            writer.write(pose, t, store.serialize_cdr(string(data=body), typename))
            if i % 10 == 0:
                status_body = json.dumps({"seq": i, "mode": "auto"})
                writer.write(status, t, store.serialize_cdr(string(data=status_body), typename))
    return directory


def write_split_db3(directory: Path) -> Path:
    """The padded poses split over two .db3 files of one directory, as rosbag2 splits a long recording
    (metadata.yaml lists both, with the counts summed)."""
    halves = [
        write_padded_db3(directory.with_name(f"{directory.name}-{n}"), count=COUNT // 2, first=n * COUNT // 2)
        for n in (0, 1)
    ]
    directory.mkdir()
    info = yaml.safe_load((halves[0] / "metadata.yaml").read_text())["rosbag2_bagfile_information"]
    names = [f"{directory.name}_{n}.db3" for n in (0, 1)]
    for half, name in zip(halves, names, strict=True):
        shutil.move(next(half.glob("*.db3")), directory / name)
    info["relative_file_paths"] = names
    info["message_count"] *= 2
    for entry in info["topics_with_message_count"]:
        entry["message_count"] *= 2
    info.pop("files", None)
    (directory / "metadata.yaml").write_text(yaml.safe_dump({"rosbag2_bagfile_information": info}))
    return directory


@pytest.fixture(scope="module")
def local_mcap(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return write_padded_mcap(tmp_path_factory.mktemp("ranged") / "padded.mcap")


@pytest.fixture(scope="module")
def local_db3(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return write_padded_db3(tmp_path_factory.mktemp("ranged") / "padded_db3")


FILE_BAGS = ["mcap", "ros1-none", "ros1-bz2", "ros1-lz4"]


def padded_bag(request: pytest.FixtureRequest, tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The padded bag of ``request.param``: a bare MCAP, a ROS 1 bag of each chunk compression, or a ROS 2
    sqlite3 directory (``ros2-db3``)."""
    if request.param in ("mcap", "ros2-db3"):
        path: Path = request.getfixturevalue("local_mcap" if request.param == "mcap" else "local_db3")
        return path
    compression = str(request.param).removeprefix("ros1-")
    return write_padded_ros1(tmp_path_factory.mktemp("ranged") / f"padded-{compression}.bag", compression)


@pytest.fixture(scope="module", params=[*FILE_BAGS, "ros2-db3"])
def local_bag(request: pytest.FixtureRequest, tmp_path_factory: pytest.TempPathFactory) -> Path:
    return padded_bag(request, tmp_path_factory)


@pytest.fixture(scope="module", params=FILE_BAGS)
def local_file_bag(request: pytest.FixtureRequest, tmp_path_factory: pytest.TempPathFactory) -> Path:
    return padded_bag(request, tmp_path_factory)


def s3_of(endpoint: S3Endpoint, bucket: str) -> S3Store:
    return S3Store(
        endpoint=endpoint.endpoint, access_key=endpoint.access_key, secret_key=endpoint.secret_key, bucket=bucket
    )


@pytest.fixture(scope="module")
def store(s3_server: S3Endpoint) -> S3Store:
    """One bucket for the module: the tests' weed holds 16 volumes and each bucket written takes one. Every
    test stores its bags again first (``shelve``), so one that changed an object leaves it right again."""
    created = s3_of(s3_server, f"ranged-{secrets.token_hex(4)}")
    created.ensure_bucket()
    return created


def shelve(store: S3Store, catalog: MemoryCatalog, bag: Path, work: Path, *, name: str = "padded") -> BagRecord:
    """Store and ingest ``bag`` (a file or a ROS 2 directory) as the bag-store does (ingest reads it through
    its own cache in ``work``/ingest-cache)."""
    names = [bag.name]
    if bag.is_dir():  # a recording's SQLite -shm/-wal side files are not part of the bag
        names = sorted(p.name for p in bag.iterdir() if not p.name.endswith(("-shm", "-wal")))
    sha = content_id([bag / n for n in names] if bag.is_dir() else [bag], directory=bag.is_dir())
    record, _ = Shelf(catalog, store).register(bag, names, sha, name=name, tags=[])
    files = RangedBagFiles(store, work / "ingest-cache", max_bytes=1 << 30, reads=ROOMY)
    assert Ingestor(catalog, files, files, store).ingest(record.id) == "ready"
    ready = catalog.get(record.id)
    assert ready is not None
    assert ready.etags  # the ETag the store gave is recorded
    return ready


def answers(access: BagAccess, ref: str) -> Answer:
    """Every message of the bag, and then point reads at five instants, as (topic, log time, bytes)."""
    with access.open(ref) as bag:
        found = [(m.connection.topic, m.log_time_ns, m.data) for m in bag.reader.messages()]
        for i in (0, 777, 1500, 2222, COUNT - 1):
            near = bag.nearest("/pose", START_NS + i * PERIOD_NS + 3)
            found.append((near.connection.topic, near.log_time_ns, near.data))
    return found


def local_answers(path: Path) -> Answer:
    with open_bag(path) as bag:
        found = [(m.connection.topic, m.log_time_ns, m.data) for m in bag.messages()]
        by_time = {t: (topic, t, data) for topic, t, data in found if topic == "/pose"}
    return found + [by_time[START_NS + i * PERIOD_NS] for i in (0, 777, 1500, 2222, COUNT - 1)]


def test_answers_by_range_equal_the_local_file_and_a_point_read_fetches_a_few_chunks(
    store: S3Store, local_bag: Path, tmp_path: Path
) -> None:
    catalog = MemoryCatalog()
    record = shelve(store, catalog, local_bag, tmp_path)
    forget_topic_stats()  # as a service process would open it: ingest counted a .db3's rows in this one
    files = RangedBagFiles(store, tmp_path / "service-cache", max_bytes=1 << 30, reads=ROOMY)
    access = BagAccess(catalog, files)
    with access.open("padded") as bag:
        near = bag.nearest("/pose", START_NS + 1234 * PERIOD_NS)
    assert near.log_time_ns == START_NS + 1234 * PERIOD_NS
    point = files.blocks.counters.fetched_bytes
    assert point < record.size_bytes / 4, f"a point read fetched {point} of {record.size_bytes} bytes"
    assert answers(access, record.id) == local_answers(local_bag)
    assert not (tmp_path / "service-cache" / record.id).exists()  # no whole copy in the service's cache
    fetched = files.blocks.counters.fetched_bytes
    assert answers(access, record.id) == local_answers(local_bag)  # warm: every block from disk
    assert files.blocks.counters.fetched_bytes == fetched
    assert files.blocks.counters.hits > 0
    assert not (tmp_path / "ingest-cache" / record.id).exists()  # ingest dropped the whole copy it read
    ingested_here = RangedBagFiles(store, tmp_path / "ingest-cache", max_bytes=1 << 30, reads=ROOMY)
    assert ingested_here.reader_for(record)[0] == Path("padded")  # the ingesting worker reads by range too


def all_messages(reader: BagReader) -> Answer:
    return [(m.connection.topic, m.log_time_ns, m.data) for m in reader.messages()]


def summary_of(reader: BagReader) -> BagSummary:
    return replace(reader.summary(), path="")  # the path names the local directory or the bag


def ros2_directory(kind: str, corpus: Path, work: Path) -> Path:
    """A recorded ROS 2 directory of the corpus (``ros2_mcap/...``), or the scenario bag written as one."""
    if kind.startswith("ros2_"):
        return corpus / kind
    work.mkdir(parents=True, exist_ok=True)
    if kind == "split-db3":
        return write_split_db3(work / "split_db3")
    if kind == "mcap-zstd-message":
        write_ros2_compressed(work / "scenario-message", StoragePlugin.MCAP, CompressionMode.MESSAGE)
        return work / "scenario-message"
    return write_compressed(cast(CompressedKind, kind), work)


@pytest.mark.parametrize(
    "kind",
    [
        "ros2_mcap/rosbag2_wbag_split",  # five storage files listed in metadata.yaml
        "ros2_mcap/replay_testing_cmd_vel",  # two storage files, no metadata.yaml
        "ros2_mcap/rosbag2_cdr_test",
        "mcap-zstd",  # zstd chunks
        "mcap-zstd-message",  # compression_mode: message
        "ros2_db3/rosbag2_cdr_test",  # sqlite3 storage
        "ros2_db3/plotjuggler_imu_pose_battery",  # recorded with -shm/-wal side files, which are not stored
        "ros2_db3/rosbag2_service_events",
        "sqlite3-zstd-message",
        "split-db3",  # two .db3 files
    ],
)
def test_a_ros2_directory_of_mcap_or_sqlite3_files_is_read_by_range_and_ingest_keeps_no_whole_copy(
    store: S3Store, corpus: Path, kind: str, tmp_path: Path
) -> None:
    local = ros2_directory(kind, corpus, tmp_path / "written")
    catalog = MemoryCatalog()
    record = shelve(store, catalog, local, tmp_path, name="ros2")
    assert record.layout == "directory"
    assert not (tmp_path / "ingest-cache" / record.id).exists()  # ingest dropped the whole copy it read
    files = RangedBagFiles(store, tmp_path / "service-cache", max_bytes=1 << 30, reads=ROOMY)
    access = BagAccess(catalog, files)
    assert files.reader_for(record)[0] == Path("ros2")  # not a local path: read by range
    with access.open("ros2") as bag, open_bag(local) as embedded:
        assert summary_of(bag.reader) == summary_of(embedded)
        expected = all_messages(embedded)
        assert all_messages(bag.reader) == expected
        for topic in {topic for topic, _, _ in expected}:
            times = [t for name, t, _ in expected if name == topic]
            near = bag.nearest(topic, times[len(times) // 2])
            assert near.log_time_ns == times[len(times) // 2]
            assert (topic, near.log_time_ns, near.data) in expected
    assert files.blocks.counters.fetched_bytes > 0
    assert not (tmp_path / "service-cache" / record.id).exists()  # no whole copy where it is read either


def test_a_split_db3_directory_opens_and_answers_a_point_read_without_reading_its_files_whole(
    store: S3Store, tmp_path: Path
) -> None:
    """The catalog's per-topic totals stand for each file's count (a scan of every row)."""
    local = write_split_db3(tmp_path / "split_db3")
    catalog = MemoryCatalog()
    record = shelve(store, catalog, local, tmp_path, name="split")
    forget_topic_stats()  # as a service process would open it: ingest counted the rows in this one
    files = RangedBagFiles(store, tmp_path / "service-cache", max_bytes=1 << 30, reads=ROOMY)
    with BagAccess(catalog, files).open("split") as bag, open_bag(local) as embedded:
        near = bag.nearest("/pose", START_NS + 2222 * PERIOD_NS)
        point = files.blocks.counters.fetched_bytes
        assert summary_of(bag.reader) == summary_of(embedded)
        assert not summary_of(bag.reader).notes  # metadata.yaml's counts agree with the catalog's
    assert near.log_time_ns == START_NS + 2222 * PERIOD_NS
    assert point < record.size_bytes / 4, f"opening and a point read fetched {point} of {record.size_bytes} bytes"


def test_a_bag_whose_ingest_failed_leaves_no_whole_copy(store: S3Store, local_mcap: Path, tmp_path: Path) -> None:
    cut = tmp_path / "cut.mcap"
    cut.write_bytes(local_mcap.read_bytes()[: local_mcap.stat().st_size // 2])  # ends inside a chunk
    catalog = MemoryCatalog()
    record, _ = Shelf(catalog, store).register(cut, [cut.name], content_id([cut], directory=False), name="cut", tags=[])
    files = RangedBagFiles(store, tmp_path / "ingest-cache", max_bytes=1 << 30, reads=ROOMY)
    assert Ingestor(catalog, files, files, store).ingest(record.id) == "failed"
    assert not (tmp_path / "ingest-cache" / record.id).exists()


def check_a_shorter_file_is_refused(
    store: S3Store, catalog: MemoryCatalog, record: BagRecord, tmp_path: Path, *, size: int, cut: int
) -> None:
    """A file of the ROS 2 directory ``record`` stored ``cut`` bytes shorter (of ``size``) is refused, naming the
    bag, with no ETag to compare: by the file's recorded size, or, for a bag stored before sizes and ETags were
    recorded, by the directory's sum."""
    catalog.replace(record.model_copy(update={"etags": {}}))
    sized = BagAccess(catalog, RangedBagFiles(store, tmp_path / "sized", max_bytes=1 << 30, reads=ROOMY))
    shorter = rf"bag {record.name} changed .*\({size - cut} bytes, the catalog recorded {size}\)"
    with pytest.raises(DamagedBagError, match=shorter), sized.open(record.name):
        pass
    catalog.replace(record.model_copy(update={"etags": {}, "file_sizes": {}}))
    older = BagAccess(catalog, RangedBagFiles(store, tmp_path / "older", max_bytes=1 << 30, reads=ROOMY))
    in_all = rf"bag {record.name} changed .*bytes in all, the catalog"
    with pytest.raises(DamagedBagError, match=in_all), older.open(record.name):
        pass


def test_a_changed_file_of_a_ros2_directory_is_an_error_naming_the_bag(
    store: S3Store, corpus: Path, tmp_path: Path
) -> None:
    local = corpus / "ros2_mcap/rosbag2_wbag_split"
    catalog = MemoryCatalog()
    record = shelve(store, catalog, local, tmp_path, name="split")
    altered = bytearray((local / "wbag_1.mcap").read_bytes())
    altered[len(altered) // 2] ^= 0xFF
    store.put_bytes(keys.bag_file(record.id, "wbag_1.mcap"), bytes(altered))
    fresh = BagAccess(catalog, RangedBagFiles(store, tmp_path / "a", max_bytes=1 << 30, reads=ROOMY))
    with pytest.raises(DamagedBagError, match=r"bag split changed in the object store .*ETag"), fresh.open("split"):
        pass
    store.put_bytes(keys.bag_file(record.id, "wbag_1.mcap"), bytes(altered[:-100]))
    check_a_shorter_file_is_refused(store, catalog, record, tmp_path, size=len(altered), cut=100)


@pytest.mark.parametrize("kind", ["mcap-zstd-file", "sqlite3-zstd-file"])
def test_zstd_file_directories_are_still_copied_whole_and_answer_right(
    store: S3Store, corpus: Path, kind: str, tmp_path: Path
) -> None:
    local = ros2_directory(kind, corpus, tmp_path / "written")
    catalog = MemoryCatalog()
    record = shelve(store, catalog, local, tmp_path, name="whole")
    files = RangedBagFiles(store, tmp_path / "service-cache", max_bytes=1 << 30, reads=ROOMY)
    with closing(BagAccess(catalog, files)) as access, access.open("whole") as bag, open_bag(local) as embedded:
        assert all_messages(bag.reader) == all_messages(embedded)
    assert (tmp_path / "service-cache" / record.id / record.files[-1]).is_file()  # opened by path
    assert files.blocks.counters.fetched_bytes == 0


@pytest.mark.parametrize("page_bytes", [1024, 65536])
def test_sqlite3_pages_smaller_or_larger_than_a_block_answer_right_within_the_cache_bound(
    store: S3Store, local_db3: Path, tmp_path: Path, page_bytes: int
) -> None:
    """SMALL's 16 KiB blocks hold sixteen 1 KiB pages, or a quarter of a 64 KiB page (read as one run)."""
    local = tmp_path / f"paged_{page_bytes}"
    shutil.copytree(local_db3, local)
    with closing(sqlite3.connect(next(local.glob("*.db3")))) as db:
        db.execute("PRAGMA journal_mode=DELETE")
        db.execute(f"PRAGMA page_size={page_bytes}")
        db.execute("VACUUM")
        assert db.execute("PRAGMA page_size").fetchone() == (page_bytes,)
    catalog = MemoryCatalog()
    record = shelve(store, catalog, local, tmp_path, name="paged")
    files = RangedBagFiles(store, tmp_path / "small-cache", max_bytes=1 << 30, reads=SMALL)
    assert answers(BagAccess(catalog, files), record.id) == local_answers(local)
    assert files.blocks.used_bytes() <= SMALL.cache_bytes
    assert not (tmp_path / "small-cache" / record.id).exists()


def test_a_db3_stored_with_its_wal_file_is_copied_whole_and_the_rows_in_the_wal_are_read(
    store: S3Store, local_db3: Path, tmp_path: Path
) -> None:
    """A directory without metadata.yaml keeps every file it came with: a ``-wal`` holding committed rows
    the database file lacks is read from a whole copy, as the local directory is read, never by range."""
    recorded = tmp_path / "recorded"
    recorded.mkdir()
    name = next(local_db3.glob("*.db3")).name
    shutil.copy(local_db3 / name, recorded / name)
    live = sqlite3.connect(recorded / name)
    live.execute("PRAGMA journal_mode=WAL")
    live.execute("PRAGMA wal_autocheckpoint=0")
    live.execute(
        "INSERT INTO messages (topic_id, timestamp, data) SELECT topic_id, timestamp + 60000000000, data "
        "FROM messages WHERE id <= 50"
    )
    live.commit()
    stored = tmp_path / "with_wal"
    stored.mkdir()
    for member in (name, f"{name}-wal"):
        shutil.copy(recorded / member, stored / member)  # while the writer is open: the rows are in the WAL
    live.close()
    names = sorted(p.name for p in stored.iterdir())
    assert names == [name, f"{name}-wal"]
    catalog = MemoryCatalog()
    record, _ = Shelf(catalog, store).register(
        stored, names, content_id([stored / n for n in names], directory=True), name="walled", tags=[]
    )
    files = RangedBagFiles(store, tmp_path / "cache", max_bytes=1 << 30, reads=ROOMY)
    assert Ingestor(catalog, files, files, store).ingest(record.id) == "ready"
    with closing(BagAccess(catalog, files)) as access, access.open("walled") as bag, open_bag(stored) as embedded:
        expected = all_messages(embedded)
        assert len(expected) == COUNT + COUNT // 10 + 50
        assert all_messages(bag.reader) == expected
    assert (tmp_path / "cache" / record.id / name).is_file()  # opened by path, beside its -wal
    assert files.blocks.counters.fetched_bytes == 0


def test_a_bag_many_times_larger_than_the_cache_answers_right_and_the_cache_keeps_its_bound(
    store: S3Store, local_bag: Path, tmp_path: Path
) -> None:
    catalog = MemoryCatalog()
    record = shelve(store, catalog, local_bag, tmp_path)
    assert record.size_bytes > 4 * SMALL.cache_bytes
    files = RangedBagFiles(store, tmp_path / "small-cache", max_bytes=1 << 30, reads=SMALL)
    access = BagAccess(catalog, files)
    expected = local_answers(local_bag)
    for _ in range(2):
        assert answers(access, record.id) == expected
        assert files.blocks.used_bytes() <= SMALL.cache_bytes
    assert files.blocks.counters.evicted_blocks > 0


def ingested_in_a_small_cache(store: S3Store, bag: Path, tmp_path: Path) -> tuple[BagRecord, int]:
    """``bag`` (a file or a ROS 2 directory) stored and ingested through SMALL's block cache, checked to stay
    within its bound and leave no whole copy; the ready record and the bytes the ingest fetched."""
    catalog = MemoryCatalog()
    names = sorted(p.name for p in bag.iterdir()) if bag.is_dir() else [bag.name]
    sha = content_id([bag / n for n in names] if bag.is_dir() else [bag], directory=bag.is_dir())
    record, _ = Shelf(catalog, store).register(bag, names, sha, name="big", tags=[])
    assert record.size_bytes > 4 * SMALL.cache_bytes
    files = RangedBagFiles(store, tmp_path / "ingest-cache", max_bytes=1 << 30, reads=SMALL)
    assert Ingestor(catalog, files, files, store).ingest(record.id) == "ready"
    assert files.blocks.used_bytes() <= SMALL.cache_bytes
    assert not (tmp_path / "ingest-cache" / record.id).exists()
    ready = catalog.get(record.id)
    assert ready is not None
    assert ready.summary is not None
    return ready, files.blocks.counters.fetched_bytes


def test_ingest_streams_a_bag_larger_than_the_cache_by_range_and_keeps_no_whole_copy(
    store: S3Store, local_file_bag: Path, tmp_path: Path
) -> None:
    """Ingest reads the bag through the block cache (its format from the first bytes), within the cache's
    bound, and only what its summary and index need: here the padding topics' chunks are never fetched (a
    whole copy fetched first would fetch every byte and no block at all)."""
    ready, fetched = ingested_in_a_small_cache(store, local_file_bag, tmp_path)
    assert 0 < fetched < ready.size_bytes / 4
    with open_bag(local_file_bag) as bag:
        assert ready.summary is not None
        assert ready.summary.message_count == bag.summary().message_count


def test_ingest_streams_a_db3_larger_than_the_cache_by_range_and_keeps_no_whole_copy(
    store: S3Store, local_db3: Path, tmp_path: Path
) -> None:
    """A .db3 has no chunks to leave out and no catalog counts yet: its ingest counts each topic's rows, a
    scan of every page, through the bounded block cache, never a whole copy."""
    forget_topic_stats()  # as a worker process would: an earlier test here may have counted this .db3
    ready, fetched = ingested_in_a_small_cache(store, local_db3, tmp_path)
    assert fetched >= 0.9 * ready.size_bytes
    with open_bag(local_db3) as bag:
        expected = [(t.name, t.count, t.first_ns, t.last_ns) for t in bag.summary().topics]
    assert ready.summary is not None
    assert [(t.name, t.count, t.first_ns, t.last_ns) for t in ready.summary.topics] == expected


def test_an_object_changed_under_the_catalog_is_an_error_naming_the_bag(
    store: S3Store, local_mcap: Path, tmp_path: Path
) -> None:
    catalog = MemoryCatalog()
    record = shelve(store, catalog, local_mcap, tmp_path, name="changing")
    opened = BagAccess(catalog, RangedBagFiles(store, tmp_path / "a", max_bytes=1 << 30, reads=ROOMY))
    with opened.open("changing") as bag:  # open now: the reader keeps the ETag it was opened with
        bag.nearest("/pose", START_NS)
    altered = bytearray(local_mcap.read_bytes())
    altered[len(altered) // 2] ^= 0xFF  # the same size, other bytes (inside a chunk of /pose)
    store.put_bytes(keys.bag_file(record.id, record.files[0]), bytes(altered))

    fresh = BagAccess(catalog, RangedBagFiles(store, tmp_path / "b", max_bytes=1 << 30, reads=ROOMY))
    with (
        pytest.raises(DamagedBagError, match=r"bag changing changed in the object store .*ETag"),
        fresh.open("changing"),
    ):
        pass
    with (
        pytest.raises(DamagedBagError, match="bag changing changed in the object store"),
        opened.open("changing") as bag,
    ):
        list(bag.reader.messages(["/pose"]))  # blocks not read before come back with another ETag

    store.put_bytes(keys.bag_file(record.id, record.files[0]), bytes(altered[:-100]))
    unrecorded = record.model_copy(update={"etags": {}})  # a bag stored before ETags were recorded
    catalog.replace(unrecorded)
    other = BagAccess(catalog, RangedBagFiles(store, tmp_path / "c", max_bytes=1 << 30, reads=ROOMY))
    with pytest.raises(DamagedBagError, match=r"bag changing changed .*the catalog recorded"), other.open("changing"):
        pass


def test_a_changed_sqlite3_file_is_an_error_naming_the_bag_while_open_and_on_open(
    store: S3Store, local_db3: Path, tmp_path: Path
) -> None:
    catalog = MemoryCatalog()
    record = shelve(store, catalog, local_db3, tmp_path, name="pages")
    name = next(n for n in record.files if n.endswith(".db3"))
    opened = BagAccess(catalog, RangedBagFiles(store, tmp_path / "a", max_bytes=1 << 30, reads=ROOMY))
    with opened.open("pages") as bag:  # open now: SQLite's file keeps the ETag it was opened with
        bag.nearest("/pose", START_NS)
    altered = bytearray((local_db3 / name).read_bytes())
    altered[len(altered) // 2] ^= 0xFF  # the same size, other bytes (inside a page of rows)
    store.put_bytes(keys.bag_file(record.id, name), bytes(altered))

    fresh = BagAccess(catalog, RangedBagFiles(store, tmp_path / "b", max_bytes=1 << 30, reads=ROOMY))
    with pytest.raises(DamagedBagError, match=r"bag pages changed in the object store .*ETag"), fresh.open("pages"):
        pass
    with (
        pytest.raises(DamagedBagError, match="bag pages changed in the object store"),
        opened.open("pages") as bag,
    ):
        list(bag.reader.messages(["/pose"]))  # pages not read before come back with another ETag
    store.put_bytes(keys.bag_file(record.id, name), bytes(altered[:-4096]))  # a page shorter
    check_a_shorter_file_is_refused(store, catalog, record, tmp_path, size=len(altered), cut=4096)


def read_in_child(endpoint: S3Endpoint, bucket: str, record_json: str, cache: str) -> tuple[str, int, int]:
    """In a process of its own: the digest of the bag's answers, the bytes it fetched and its cache misses."""
    record = BagRecord.model_validate_json(record_json)
    catalog = MemoryCatalog()
    catalog.add(record)
    files = RangedBagFiles(s3_of(endpoint, bucket), Path(cache), max_bytes=1 << 30, reads=ROOMY)
    found = answers(BagAccess(catalog, files), record.id)
    digest = hashlib.sha256(repr(found).encode()).hexdigest()
    return digest, files.blocks.counters.fetched_bytes, files.blocks.counters.misses


def test_two_processes_reading_one_bag_at_once_fetch_each_block_once(
    store: S3Store, s3_server: S3Endpoint, local_mcap: Path, tmp_path: Path
) -> None:
    catalog = MemoryCatalog()
    record = shelve(store, catalog, local_mcap, tmp_path)
    cache = str(tmp_path / "host-cache")
    with ProcessPoolExecutor(2, mp_context=get_context("spawn")) as pool:
        runs = [pool.submit(read_in_child, s3_server, store.bucket, record.model_dump_json(), cache) for _ in range(2)]
        results = [run.result(timeout=120) for run in runs]
    expected = hashlib.sha256(repr(local_answers(local_mcap)).encode()).hexdigest()
    assert [digest for digest, _, _ in results] == [expected, expected]
    assert sum(fetched for _, fetched, _ in results) == record.size_bytes  # every byte fetched once


@pytest.fixture
def restartable_s3(tmp_path: Path) -> Iterator[tuple[Restartable, S3Endpoint]]:
    server, endpoint, sockets = weed_server(tmp_path / "weed")
    with ExitStack() as stack:
        stack.callback(lambda: remove_weed_sockets(sockets))
        stack.callback(server.stop)
        server.start()
        yield server, endpoint


def test_the_object_store_stopped_mid_read_is_a_clear_error_and_the_next_call_works(
    restartable_s3: tuple[Restartable, S3Endpoint], local_mcap: Path, tmp_path: Path
) -> None:
    server, endpoint = restartable_s3
    store = s3_of(endpoint, "ranged")
    store.ensure_bucket()
    catalog = MemoryCatalog()
    record = shelve(store, catalog, local_mcap, tmp_path)
    access = BagAccess(catalog, RangedBagFiles(store, tmp_path / "svc", max_bytes=1 << 30, reads=SMALL))
    with access.open(record.id) as bag:
        bag.nearest("/pose", START_NS)  # open: summary read, reader cached
    server.stop()
    down = rf"bag padded could not be read after 3 tries: .*{endpoint.endpoint}"
    with pytest.raises(StorageError, match=down), access.open(record.id) as bag:
        list(bag.reader.messages(["/pose"]))
    server.start()
    assert answers(access, record.id) == local_answers(local_mcap)
