"""A compressed chunk or message that does not decompress is a DamagedBagError naming the file, in every
format and compression (never a zstd, lz4 or bz2 library error), whether it is met on opening or later."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest
import zstandard

from bagmcp_shared import budget
from bagmcp_shared.bags import open_bag
from bagmcp_shared.errors import DamagedBagError, UnsupportedFormatError
from bagmcp_shared.settings import InputBudget
from tests.fixtures.compressed_bags import CompressedKind
from tests.fixtures.damage import (
    corrupt_at,
    corrupt_db3_message,
    corrupt_mcap_chunk,
    corrupt_ros1_chunk,
)
from tests.fixtures.inprocess import copy_bags
from tests.fixtures.mcap_cuts import write_mcap


def _read_everything(path: Path) -> None:
    with open_bag(path) as bag:
        bag.summary()
        for raw in bag.messages():
            bag.decode(raw)


def _storage(bag: Path) -> Path:
    return next(p for p in bag.iterdir() if p.name != "metadata.yaml")


@pytest.mark.parametrize(
    ("kind", "damage"),
    [
        ("ros1-bz2", lambda p: corrupt_ros1_chunk(p, 0)),
        ("ros1-lz4", lambda p: corrupt_ros1_chunk(p, 0)),
        ("mcap-lz4", lambda p: corrupt_mcap_chunk(p, 0)),
        ("mcap-zstd", lambda p: corrupt_mcap_chunk(_storage(p), 0)),
        ("mcap-zstd-file", lambda p: corrupt_at(_storage(p), 0.0)),
        ("sqlite3-zstd-file", lambda p: corrupt_at(_storage(p), 0.5)),
        ("sqlite3-zstd-message", lambda p: corrupt_db3_message(_storage(p), 10)),
    ],
)
def test_data_that_does_not_decompress_is_a_damaged_bag_error_naming_the_file(
    tmp_path: Path, compressed_bags: dict[CompressedKind, Path], kind: CompressedKind, damage: object
) -> None:
    path = copy_bags([compressed_bags[kind]], tmp_path) / compressed_bags[kind].name
    assert callable(damage)
    damage(path)
    with pytest.raises(DamagedBagError) as caught:
        _read_everything(path)
    message = str(caught.value)
    assert message.startswith(str(path))
    assert "\n" not in message
    assert "/tmp/bagmcp-" not in message  # never a server's temporary path


def test_an_indexed_mcap_with_a_damaged_middle_chunk_opens_and_fails_when_that_chunk_is_read(tmp_path: Path) -> None:
    path = tmp_path / "chunks.mcap"
    write_mcap(path, "zstd")
    intact = tmp_path / "intact.mcap"
    shutil.copy(path, intact)
    corrupt_mcap_chunk(path, 1)
    with open_bag(path) as bag, open_bag(intact) as good:
        assert bag.summary().message_count == good.summary().message_count  # from the summary section
        with pytest.raises(DamagedBagError, match="damaged and cannot be read"):
            sum(1 for _ in bag.messages())


def test_an_indexed_mcap_with_a_damaged_first_chunk_opens_from_its_indexes_and_fails_when_it_is_read(
    tmp_path: Path,
) -> None:
    """The summary's times come from the message indexes, so no chunk is decompressed to open the bag (before,
    each topic's first and last chunk was, which refused this file on opening); reading the chunk fails."""
    path = tmp_path / "first.mcap"
    write_mcap(path, "zstd")
    corrupt_mcap_chunk(path, 0)
    with open_bag(path) as bag:
        assert bag.summary().message_count == 2400
        with pytest.raises(DamagedBagError, match="ZstdError"):
            sum(1 for _ in bag.messages())


def test_a_compressed_storage_file_that_expands_like_a_bomb_is_refused_while_it_is_written(
    tmp_path: Path, compressed_bags: dict[CompressedKind, Path], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(budget, "_current", InputBudget(expansion_floor_bytes=1 << 20))
    source = compressed_bags["sqlite3-zstd-file"]
    bag = copy_bags([source], tmp_path) / source.name
    storage = _storage(bag)
    with storage.open("wb") as out, zstandard.ZstdCompressor().stream_writer(out) as packed:
        for _ in range(64):
            packed.write(bytes(1 << 20))  # 64 MiB of zeros in a few kilobytes
    assert storage.stat().st_size < 64 << 10
    with pytest.raises(UnsupportedFormatError, match="expands more than 200 times when decompressed"):
        open_bag(bag)
