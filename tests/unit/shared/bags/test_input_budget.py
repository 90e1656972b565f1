"""Compressed records and user YAML are checked against the memory budget before anything is expanded.

These run at small sizes under a small budget (no process here may expand a real bomb; the full-size ones
run in tests/integration/test_memory_capped.py, in a process whose address space is capped)."""

from __future__ import annotations

import bz2
import io
import sqlite3
import tracemalloc
from pathlib import Path

import lz4.frame  # type: ignore[import-untyped]
import pytest
import zstandard
from mcap.writer import CompressionType, Writer

from bagmcp_shared import budget
from bagmcp_shared.bags import BagFormat, open_bag, open_stream
from bagmcp_shared.bags.ros1_chunks import chunk_decompressor
from bagmcp_shared.bags.user_yaml import UserYamlError, load_user_yaml, refuse_aliases
from bagmcp_shared.errors import UnsupportedFormatError
from bagmcp_shared.settings import InputBudget
from tests.fixtures.compressed_bags import CompressedKind
from tests.fixtures.hostile_inputs import (
    alias_bomb_lines,
    write_mcap_chunk_bomb,
    write_ros1_chunk_bomb,
    write_yaml_alias_bomb,
)
from tests.fixtures.inprocess import copy_bags
from tests.fixtures.mcap_cuts import cut_copy

EXPANDED = 4 << 20


@pytest.fixture
def small_budget(monkeypatch: pytest.MonkeyPatch) -> InputBudget:
    """4 MiB records are past it: 1 MiB floor, at most 2 MiB."""
    small = InputBudget(max_record_bytes=2 << 20, expansion_floor_bytes=1 << 20)
    monkeypatch.setattr(budget, "_current", small)
    return small


def test_an_indexed_mcap_chunk_past_the_budget_is_refused_on_opening(tmp_path: Path, small_budget: None) -> None:
    path = write_mcap_chunk_bomb(tmp_path / "bomb.mcap", expanded=EXPANDED)
    with pytest.raises(UnsupportedFormatError, match=r"bomb\.mcap: the zstd chunk at byte 36 declares 4,194,"):
        open_bag(path)


def test_a_chunk_within_the_budget_is_read(tmp_path: Path) -> None:
    path = write_mcap_chunk_bomb(tmp_path / "fine.mcap", expanded=EXPANDED)
    with open_bag(path) as bag:
        assert [len(m.data) for m in bag.messages()] == [EXPANDED]


def test_an_mcap_read_from_start_to_end_refuses_the_chunk_too(tmp_path: Path, small_budget: None) -> None:
    """Without its summary (cut after the data) the file is scanned; the chunk is refused before decompressing."""
    whole = write_mcap_chunk_bomb(tmp_path / "whole.mcap", expanded=EXPANDED)
    cut = cut_copy(whole, whole.stat().st_size - 40, tmp_path / "cut.mcap")
    with pytest.raises(UnsupportedFormatError, match=r"cut\.mcap: the zstd chunk at byte 36 declares"):
        open_bag(cut, recover_truncated=True)


def test_a_ros1_chunk_past_the_budget_is_refused_on_opening(tmp_path: Path, small_budget: None) -> None:
    path = write_ros1_chunk_bomb(tmp_path, expanded=EXPANDED)
    with pytest.raises(UnsupportedFormatError, match=r"the bz2 chunk at byte 4,109 declares 4,19"):
        open_bag(path)


def test_a_ros1_chunk_that_lies_about_its_size_stops_at_the_budget(tmp_path: Path, small_budget: None) -> None:
    path = write_ros1_chunk_bomb(tmp_path, expanded=EXPANDED, declared=1000)
    with (
        open_bag(path) as bag,
        pytest.raises(UnsupportedFormatError, match="holds more than 1,048,576 bytes uncompressed"),
    ):
        list(bag.messages())


def test_a_ros1_chunk_within_the_budget_is_read_whole(tmp_path: Path) -> None:
    path = write_ros1_chunk_bomb(tmp_path, expanded=EXPANDED)
    with open_bag(path) as bag:
        (message,) = list(bag.messages())
        assert bag.decode(message).data == "a" * EXPANDED  # type: ignore[attr-defined]


def test_a_metadata_yaml_with_aliases_is_refused_naming_the_first(tmp_path: Path) -> None:
    bag = write_yaml_alias_bomb(tmp_path, levels=2)
    with pytest.raises(UnsupportedFormatError, match=r"metadata.yaml uses the YAML alias \*l0 at line 2"):
        open_bag(bag)


def test_user_yaml_loads_without_aliases_and_bounds_its_size() -> None:
    assert load_user_yaml("a: [1, 2]\nb: {c: d}\n") == {"a": [1, 2], "b": {"c": "d"}}
    with pytest.raises(UserYamlError, match=r"alias \*l0 at line 2"):
        load_user_yaml("\n".join(alias_bomb_lines(2)))
    with pytest.raises(UserYamlError, match="more than the 4,194,304 accepted"):
        load_user_yaml("#" * (5 << 20))


def test_qos_profiles_are_checked_for_aliases_before_rosbags_parses_them() -> None:
    assert refuse_aliases("- history: 1\n  depth: 10\n") == "- history: 1\n  depth: 10\n"
    with pytest.raises(UserYamlError, match=r"alias \*q"):
        refuse_aliases("- &q {history: 1}\n- *q\n")


def test_an_mcap_read_from_start_to_end_skips_attachments_instead_of_loading_them(tmp_path: Path) -> None:
    """The pass over a file without a summary read each top-level record whole: a 16 MiB attachment cost
    16 MiB (and one of gigabytes, gigabytes); now only its first bytes, which name it, are read."""
    path = tmp_path / "attached.mcap"
    with path.open("wb") as file:
        writer = Writer(file)
        writer.start(profile="ros2", library="bagmcp tests")
        schema = writer.register_schema(name="std_msgs/msg/String", encoding="ros2msg", data=b"string data")
        channel = writer.register_channel("/chatter", "cdr", schema)
        writer.add_attachment(log_time=1, create_time=1, name="big.bin", media_type="x", data=bytes(16 << 20))
        writer.add_message(channel, log_time=2, data=b"\x00\x01\x00\x00\x01\x00\x00\x00\x00", publish_time=2)
        writer.finish()  # type: ignore[no-untyped-call]
    cut = cut_copy(path, path.stat().st_size - 30, tmp_path / "cut.mcap")  # no footer: read from start to end
    tracemalloc.start()
    try:
        with open_bag(cut, recover_truncated=True) as bag:
            assert [m.log_time_ns for m in bag.messages()] == [2]
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert peak < 4 << 20, peak


def test_a_message_compressed_per_message_past_the_budget_is_refused(
    tmp_path: Path, compressed_bags: dict[CompressedKind, Path], small_budget: None
) -> None:
    """zstd allocates the size a frame declares before it decompresses; 4 MiB of zeros fit in a few hundred
    bytes."""
    source = compressed_bags["sqlite3-zstd-message"]
    bag = copy_bags([source], tmp_path) / source.name
    db3 = next(p for p in bag.iterdir() if p.suffix == ".db3")
    with sqlite3.connect(db3) as db:
        first = db.execute("SELECT id FROM messages ORDER BY timestamp LIMIT 1").fetchone()[0]
        db.execute("UPDATE messages SET data = ? WHERE id = ?", (zstandard.compress(bytes(EXPANDED)), first))
    with open_bag(bag) as opened, pytest.raises(UnsupportedFormatError, match="a zstd-compressed message on /"):
        list(opened.messages())


def test_an_lz4_chunk_that_lies_about_its_size_stops_at_the_budget(tmp_path: Path, small_budget: None) -> None:
    """The mcap library's lz4 call trusts the frame alone; the chunk declares 1,000 bytes and holds 4 MiB."""
    path = write_mcap_chunk_bomb(tmp_path / "lies.mcap", expanded=EXPANDED, compression="lz4", declared=1000)
    with open_bag(path) as bag, pytest.raises(UnsupportedFormatError, match=r"lies\.mcap: an lz4 chunk holds more"):
        list(bag.messages())


def test_an_lz4_chunk_within_the_budget_is_read(tmp_path: Path) -> None:
    path = write_mcap_chunk_bomb(tmp_path / "fine.mcap", expanded=EXPANDED, compression="lz4")
    with open_bag(path) as bag:
        assert [len(m.data) for m in bag.messages()] == [EXPANDED]


class _RangedLike(io.BytesIO):
    """A file read by range, as team mode's: it takes chunk hints and remembers where each read began."""

    def __init__(self, data: bytes) -> None:
        super().__init__(data)
        self.read_at: list[int] = []

    def hint_records(self, spans: list[tuple[int, int]]) -> None:
        self.spans = spans

    def read(self, size: int | None = -1, /) -> bytes:
        self.read_at.append(self.tell())
        return super().read(size)


def _chunked_mcap(path: Path, chunks: int) -> Path:
    with path.open("wb") as file:
        writer = Writer(file, chunk_size=1024, compression=CompressionType.ZSTD)
        writer.start(profile="ros2", library="test")
        schema = writer.register_schema("std_msgs/msg/String", "ros2msg", b"string data")
        channel = writer.register_channel("/text", "cdr", schema)
        for i in range(chunks):
            writer.add_message(channel, log_time=i * 10**9, publish_time=i * 10**9, data=bytes(2048))
        writer.finish()  # type: ignore[no-untyped-call]
    return path


def test_a_ranged_mcap_checks_its_chunk_index_without_reading_each_chunk(tmp_path: Path) -> None:
    """Ingest read the same bytes whole (their ETag pins them); fetching every chunk's head again would cost
    one block per chunk, about the whole bag."""
    path = _chunked_mcap(tmp_path / "many.mcap", chunks=20)
    stream = _RangedLike(path.read_bytes())
    with open_stream(path, stream, size=path.stat().st_size, fmt=BagFormat.MCAP) as bag:
        assert len(stream.spans) == 20
        inside = [at for at in stream.read_at for start, end in stream.spans if start <= at < end]
        assert inside == []  # no chunk was read to open the bag
        assert len(list(bag.messages())) == 20  # and every chunk reads when asked


def test_a_ranged_mcap_is_still_refused_when_its_index_declares_too_much(tmp_path: Path, small_budget: None) -> None:
    path = write_mcap_chunk_bomb(tmp_path / "bomb.mcap", expanded=EXPANDED)
    stream = _RangedLike(path.read_bytes())
    with pytest.raises(UnsupportedFormatError, match=r"bomb\.mcap: the zstd chunk at byte 36 declares 4,194,"):
        open_stream(path, stream, size=path.stat().st_size, fmt=BagFormat.MCAP)


def test_a_ranged_ros1_chunk_past_the_budget_is_refused(tmp_path: Path, small_budget: None) -> None:
    """Team mode reads ROS 1 by range (``Ros1RangeSource``), which decompressed chunks with no bound before."""
    path = write_ros1_chunk_bomb(tmp_path, expanded=EXPANDED)
    with (
        open_stream(path, _RangedLike(path.read_bytes()), size=path.stat().st_size, fmt=BagFormat.ROS1) as bag,
        pytest.raises(UnsupportedFormatError, match=r"the bz2 chunk at byte 4,109 declares 4,19"),
    ):
        list(bag.messages())


def test_a_ranged_ros1_chunk_that_lies_about_its_size_stops_at_the_budget(tmp_path: Path, small_budget: None) -> None:
    path = write_ros1_chunk_bomb(tmp_path, expanded=EXPANDED, declared=1000)
    with (
        open_stream(path, _RangedLike(path.read_bytes()), size=path.stat().st_size, fmt=BagFormat.ROS1) as bag,
        pytest.raises(UnsupportedFormatError, match="holds more than 1,048,576 bytes uncompressed"),
    ):
        bag.summary()  # the first and last times of each topic are read from its first and last chunks


def test_a_ranged_ros1_chunk_within_the_budget_is_read_whole(tmp_path: Path) -> None:
    path = write_ros1_chunk_bomb(tmp_path, expanded=EXPANDED)
    stream = _RangedLike(path.read_bytes())
    with open_stream(path, stream, size=path.stat().st_size, fmt=BagFormat.ROS1) as bag:
        (message,) = list(bag.messages())
        assert bag.decode(message).data == "a" * EXPANDED  # type: ignore[attr-defined]


@pytest.mark.parametrize("compression", ["lz4", "bz2"])
def test_a_chunk_cut_short_is_an_error_not_fewer_records(compression: str) -> None:
    """The streaming lz4 decompressor returns what a cut frame holds without a word; lz4.frame.decompress, which
    ranged reads used before, raised. A cut chunk must not read as a chunk with fewer messages."""
    whole = (lz4.frame.compress if compression == "lz4" else bz2.compress)(bytes(range(256)) * 4096)
    decompress = chunk_decompressor(Path("x.bag"), 0, compression, declared=4 << 20, compressed=len(whole))
    assert decompress(whole) == bytes(range(256)) * 4096
    with pytest.raises(EOFError):
        decompress(whole[: len(whole) // 2])
