"""A ROS 2 sqlite3 storage file read through a seekable stream (team mode's ranged file; here a local file
that counts what is read) answers as the same file opened by path, reads only what a question needs when the
catalog's topic stats are given, never opens a side file, and lets the stream's own errors through."""

from __future__ import annotations

import io
import sqlite3
from dataclasses import replace
from pathlib import Path
from typing import BinaryIO, cast

import pytest
from rosbags.typesys import Stores, get_typestore

from bagmcp_shared.bags import BagFormat, BagReader, open_bag, open_directory_stream
from bagmcp_shared.errors import DamagedBagError

STRING = "std_msgs/msg/String"
START_NS = 1_700_000_000_000_000_000
SCHEMA = """
CREATE TABLE schema(schema_version INTEGER PRIMARY KEY, ros_distro TEXT NOT NULL);
CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL,
    serialization_format TEXT NOT NULL, offered_qos_profiles TEXT NOT NULL);
CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL, timestamp INTEGER NOT NULL,
    data BLOB NOT NULL);
CREATE INDEX timestamp_idx ON messages (timestamp ASC);
INSERT INTO schema VALUES (3, 'humble');
INSERT INTO topics VALUES (1, '/pose', 'std_msgs/msg/String', 'cdr', ''),
    (2, '/status', 'std_msgs/msg/String', 'cdr', '');
"""


class CountingFile(io.FileIO):
    """A local file that counts the bytes read from it and can be told to fail past an offset."""

    def __init__(self, path: Path) -> None:
        super().__init__(path, "rb")
        self.read_bytes = 0
        self.read_at: list[int] = []
        self.fail_past: int | None = None

    def read(self, size: int | None = -1, /) -> bytes:
        if self.fail_past is not None and self.tell() > self.fail_past:
            raise DamagedBagError("bag pages changed in the object store after it was catalogued (a test)")
        self.read_at.append(self.tell())
        data = super().read(size)
        self.read_bytes += len(data)
        return data


def write_db3(directory: Path, *, count: int, pad: int, wal: bool = False) -> Path:
    """A ROS 2 sqlite3 directory (no metadata.yaml) of ``count`` strings of ``pad`` bytes on /pose at 100 Hz
    and every tenth on /status, written with sqlite3 directly (fast), in WAL mode when ``wal``."""
    store = get_typestore(Stores.ROS2_HUMBLE)
    body = bytes(store.serialize_cdr(store.types[STRING](data="x" * pad), STRING))
    status = bytes(store.serialize_cdr(store.types[STRING](data="ok"), STRING))
    directory.mkdir()
    path = directory / f"{directory.name}_0.db3"
    db = sqlite3.connect(path)
    if wal:
        db.execute("PRAGMA journal_mode=WAL")
    db.executescript(SCHEMA)
    rows: list[tuple[int, int, bytes]] = [(1, START_NS + i * 10_000_000, body) for i in range(count)]
    rows += [(2, START_NS + i * 10_000_000, status) for i in range(0, count, 10)]
    rows.sort(key=lambda row: row[1])
    db.executemany("INSERT INTO messages (topic_id, timestamp, data) VALUES (?, ?, ?)", rows)
    db.commit()
    db.close()
    return directory


def streamed(directory: Path, *, known: bool) -> tuple[BagReader, CountingFile]:
    """The directory's one .db3 opened through a counting stream, with the local file's topic stats as the
    catalog would give them when ``known``."""
    path = next(directory.glob("*.db3"))
    stream = CountingFile(path)
    stats = None
    if known:
        with open_bag(directory) as local:
            stats = {t.name: (t.count, t.first_ns, t.last_ns) for t in local.summary().topics}
    storage = {path.name: (cast(BinaryIO, stream), path.stat().st_size)}
    return open_directory_stream(Path(directory.name), None, storage, totals=stats), stream


def everything(reader: BagReader) -> list[tuple[str, int, bytes]]:
    return [(m.connection.topic, m.log_time_ns, m.data) for m in reader.messages()]


@pytest.mark.parametrize("known", [True, False])
def test_a_db3_read_through_a_stream_answers_as_the_file_opened_by_path(tmp_path: Path, known: bool) -> None:
    directory = write_db3(tmp_path / "pages", count=2000, pad=300)
    reader, _ = streamed(directory, known=known)
    with reader, open_bag(directory) as local:
        assert reader.format is BagFormat.ROS2_SQLITE3
        assert replace(reader.summary(), path="") == replace(local.summary(), path="")
        assert everything(reader) == everything(local)


def test_with_the_catalogs_stats_a_point_read_reads_a_few_pages_not_the_file(tmp_path: Path) -> None:
    directory = write_db3(tmp_path / "pages", count=20_000, pad=300)
    size = next(directory.glob("*.db3")).stat().st_size
    reader, stream = streamed(directory, known=True)
    with reader:
        at = START_NS + 12_345 * 10_000_000
        found = list(reader.messages(["/pose"], start_ns=at, stop_ns=at + 1))
        assert [m.log_time_ns for m in found] == [at]
        assert stream.read_bytes < 64 * 4096, f"a point read read {stream.read_bytes} of {size} bytes"
    unknown, scanned = streamed(directory, known=False)
    with unknown:
        assert scanned.read_bytes >= size * 0.9  # without them, counting per topic reads every row


def test_with_the_catalogs_stats_opening_reads_no_page_of_the_messages_table(tmp_path: Path) -> None:
    """Each page of the messages table or its index read on opening was a round trip to the object store before
    any answer (a root, then the first row's leaf: pages far apart in a large file)."""
    directory = write_db3(tmp_path / "pages", count=20_000, pad=300)
    with sqlite3.connect(next(directory.glob("*.db3"))) as db:
        roots = {row[0] for row in db.execute("SELECT rootpage FROM sqlite_master WHERE tbl_name = 'messages'")}
    reader, stream = streamed(directory, known=True)
    with reader:
        opened = {at // 4096 + 1 for at in stream.read_at}  # SQLite numbers pages from 1
        assert 1 in opened  # the schema
        assert not opened & roots, f"pages read on opening: {sorted(opened)}, the messages b-trees' roots: {roots}"
        assert {t.name for t in reader.summary().topics} == {"/pose", "/status"}


def test_totals_that_lack_a_topic_do_not_stand_for_the_files_counts(tmp_path: Path) -> None:
    directory = write_db3(tmp_path / "pages", count=2000, pad=30)
    path = next(directory.glob("*.db3"))
    storage = {path.name: (cast(BinaryIO, CountingFile(path)), path.stat().st_size)}
    partial = {"/pose": (1, START_NS, START_NS)}  # /status missing, and a wrong count that must not be used
    with open_directory_stream(Path("pages"), None, storage, totals=partial) as reader, open_bag(directory) as local:
        assert replace(reader.summary(), path="") == replace(local.summary(), path="")


def test_a_count_that_spills_to_scratch_files_is_right(tmp_path: Path) -> None:
    """300 000 rows: the GROUP BY that counts per topic sorts more than SQLite keeps in memory, so it opens
    a nameless scratch file, which the stream VFS leaves to the default one."""
    directory = write_db3(tmp_path / "many", count=300_000, pad=1)
    reader, _ = streamed(directory, known=False)
    with reader:
        counts = {t.name: t.count for t in reader.summary().topics}
    assert counts == {"/pose": 300_000, "/status": 30_000}


def test_a_wal_mode_db3_is_read_without_looking_for_its_side_files(tmp_path: Path) -> None:
    directory = write_db3(tmp_path / "wal", count=500, pad=50, wal=True)
    assert not list(directory.glob("*-wal"))  # checkpointed and removed on close; the header still says WAL
    reader, _ = streamed(directory, known=False)
    with reader, open_bag(directory) as local:
        assert everything(reader) == everything(local)


def test_an_error_of_the_stream_is_raised_as_it_is(tmp_path: Path) -> None:
    directory = write_db3(tmp_path / "pages", count=5000, pad=300)
    reader, stream = streamed(directory, known=True)
    stream.fail_past = 8192
    with reader, pytest.raises(DamagedBagError, match=r"^bag pages changed in the object store"):
        everything(reader)
