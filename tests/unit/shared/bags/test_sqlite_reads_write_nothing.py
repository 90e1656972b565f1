"""Reading a ROS 2 sqlite3 bag writes nothing beside it: a served folder stays as it was (SQLite opened with
``mode=ro`` alone creates ``-wal`` and ``-shm`` files beside a WAL-mode database, even read-only)."""

from __future__ import annotations

import shutil
import sqlite3
from pathlib import Path

from bagmcp_shared.bags import open_bag
from tests.fixtures.bagfactory import write_chatter_bag


def _in_wal_mode(directory: Path) -> None:
    db3 = next(directory.glob("*.db3"))
    with sqlite3.connect(db3) as db:
        assert db.execute("PRAGMA journal_mode=WAL").fetchone() == ("wal",)
    for leftover in directory.glob("*.db3-*"):  # checkpointed on close: the log is empty
        leftover.unlink()


def _read_all(directory: Path) -> int:
    with open_bag(directory) as reader:
        return sum(1 for _ in reader.messages())


def test_reading_a_wal_mode_bag_creates_no_file_beside_it(tmp_path: Path) -> None:
    bag = write_chatter_bag(tmp_path, count=200, name="wal_mode")
    _in_wal_mode(bag)
    before = sorted(p.name for p in bag.iterdir())
    assert _read_all(bag) == 200
    assert sorted(p.name for p in bag.iterdir()) == before


def test_messages_still_in_the_write_ahead_log_are_read(tmp_path: Path) -> None:
    bag = write_chatter_bag(tmp_path, count=200, name="pending")
    _in_wal_mode(bag)
    db3 = next(bag.glob("*.db3"))
    copy = tmp_path / "held"
    writer = sqlite3.connect(db3)
    writer.execute("PRAGMA wal_autocheckpoint=0")
    row = writer.execute("SELECT topic_id, timestamp, data FROM messages ORDER BY timestamp DESC LIMIT 1").fetchone()
    writer.execute("INSERT INTO messages (topic_id, timestamp, data) VALUES (?, ?, ?)", (row[0], row[1] + 1, row[2]))
    writer.commit()
    shutil.copytree(bag, copy)  # the file and its log, as a recorder that stopped before a checkpoint left them
    writer.close()
    assert (copy / f"{db3.name}-wal").stat().st_size > 0
    assert _read_all(copy) == 201
