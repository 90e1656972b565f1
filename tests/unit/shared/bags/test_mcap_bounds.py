"""A channel's first and last log time read from the MCAP message indexes equal the least and greatest time of
its messages (every message read), on generated files (chunks out of time order among them) and on every
recorded MCAP with a summary; a file without message indexes gets the same bounds from its messages."""

from __future__ import annotations

import random
from pathlib import Path

import pytest
from mcap.reader import SeekingReader
from mcap.writer import IndexType, Writer

from bagmcp_shared.bags.mcap_bounds import indexed_bounds
from bagmcp_shared.bags.mcap_source import McapSource
from tests.fixtures.bagfactory import BagKind

START_NS = 1_700_000_000_000_000_000


def every_message_bounds(path: Path) -> dict[int, tuple[int, int]]:
    """Least and greatest log time of each channel, from every message in file order."""
    found: dict[int, tuple[int, int]] = {}
    with path.open("rb") as file:
        for _schema, channel, message in SeekingReader(file).iter_messages(log_time_order=False):
            low, high = found.get(channel.id, (message.log_time, message.log_time))
            found[channel.id] = (min(low, message.log_time), max(high, message.log_time))
    return found


def source_bounds(path: Path) -> dict[int, tuple[int, int]]:
    source = McapSource(path)
    try:
        return {c.id: bounds for c in source.connections if (bounds := source.bounds(c.id)) is not None}
    finally:
        source.close()


def write_shuffled(path: Path, *, message_indexes: bool) -> None:
    """Three channels, 300 messages in log times shuffled across ~40 small chunks, so chunks overlap in time."""
    times = [START_NS + i * 10_000_000 for i in range(300)]
    random.Random(3).shuffle(times)
    kinds = IndexType.ALL if message_indexes else IndexType.CHUNK
    with path.open("wb") as file:
        writer = Writer(file, chunk_size=400, index_types=kinds)
        writer.start(profile="", library="bagmcp tests")
        channels = [writer.register_channel(f"/c{i}", "json", 0) for i in range(3)]
        for i, at_ns in enumerate(times):
            writer.add_message(channels[i % 3], log_time=at_ns, data=b'{"i": %d}' % i, publish_time=at_ns)
        writer.finish()  # type: ignore[no-untyped-call]


@pytest.mark.parametrize("message_indexes", [True, False], ids=["message indexes", "none"])
def test_chunks_out_of_time_order_give_the_messages_bounds(tmp_path: Path, message_indexes: bool) -> None:
    path = tmp_path / "shuffled.mcap"
    write_shuffled(path, message_indexes=message_indexes)
    with path.open("rb") as file:
        summary = SeekingReader(file).get_summary()
        assert summary is not None
        assert len(summary.chunk_indexes) > 20
        first_channel = min(summary.channels)
        read = indexed_bounds(file, summary.chunk_indexes, first_channel)
    expected = every_message_bounds(path)
    assert read == (expected[first_channel] if message_indexes else None)  # None: the caller reads the messages
    assert source_bounds(path) == expected


def test_generated_bags_bounds_are_their_messages(
    drive_bags: dict[BagKind, Path], scenario_bags: dict[BagKind, Path]
) -> None:
    for bag in (drive_bags["ros2-mcap"], scenario_bags["ros2-mcap"]):
        path = next(bag.glob("*.mcap"))
        expected = every_message_bounds(path)
        assert len(expected) >= 5
        assert source_bounds(path) == expected


def test_every_recorded_mcap_with_a_summary_has_its_messages_bounds(corpus: Path) -> None:
    checked = 0
    for path in sorted(corpus.rglob("*.mcap")):
        try:
            source = McapSource(path)
        except Exception:  # damaged or refused recordings: the fuzz and corpus tests cover their errors
            continue
        summarised = source._summary is not None  # the files the indexes serve
        source.close()
        if summarised:
            assert source_bounds(path) == every_message_bounds(path), path
            checked += 1
    assert checked >= 12
