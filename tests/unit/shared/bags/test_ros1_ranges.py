"""The ROS 1 range reader (index at the end, then only the chunks needed) gives exactly what rosbags'
reader gives: connections, counts, bounds, chunk compression and messages in the same order, on
recorded bags of every chunk compression (and one without chunks) and on the generated scenario and drive bags,
read from a file that takes the chunks' spans as hints (as the object store's ranged file does)."""

from __future__ import annotations

import io
import struct
from pathlib import Path

import pytest
from rosbags.rosbag1 import Writer
from rosbags.typesys import Stores, get_typestore

from bagmcp_shared.bags.ros1_chunks import header_field
from bagmcp_shared.bags.ros1_ranges import Ros1RangeSource
from bagmcp_shared.bags.ros1_source import Ros1Source
from bagmcp_shared.errors import DamagedBagError
from tests.fixtures.bagfactory import write_bag
from tests.fixtures.drive_bags import write_drive_bag
from tests.fixtures.hostile_inputs import ros1_records

STRING = "std_msgs/msg/String"
RECORDED = [
    "ros1/rosout_log/out.bag",
    "ros1/evo_tf/tf_example.bag",
    "ros1/turtlesim_rosbagjs/example.bag",
    "ros1/turtlesim_rosbagjs/example-bz2.bag",
    "ros1/turtlesim_rosbagjs/example-lz4.bag",
    "ros1/jackal_imu_odom/test2.bag",
    "ros1/datmo_scan_twist_imu/two_robots.bag",
    "edge_cases/ros1_empty_message_definition.bag",
    "edge_cases/ros1_no_messages.bag",  # no chunk: nothing to hint (uploads of it once failed here)
]


class HintedFile(io.BytesIO):
    """A bag's bytes in memory that keeps the record spans the reader hints, as the ranged S3 file takes them."""

    def __init__(self, path: Path) -> None:
        super().__init__(path.read_bytes())
        self.hints: list[list[tuple[int, int]]] = []

    def hint_records(self, spans: list[tuple[int, int]]) -> None:
        self.hints.append(spans)


def assert_same(path: Path) -> None:
    stream = HintedFile(path)
    expected, ranged = Ros1Source(path), Ros1RangeSource(path, stream)
    try:
        assert len(stream.hints) == 1
        assert all(start < end for start, end in stream.hints[0])
        assert list(ranged.connections) == list(expected.connections)
        assert ranged.compression == expected.compression
        ids = [c.id for c in expected.connections]
        assert [ranged.bounds(i) for i in ids] == [expected.bounds(i) for i in ids]
        everything = list(expected.messages(ids, start_ns=None, stop_ns=None))
        assert list(ranged.messages(ids, start_ns=None, stop_ns=None)) == everything
        if everything:  # the middle third, connections asked for in reverse order (ties follow that order)
            first, last = everything[0].log_time_ns, everything[-1].log_time_ns
            lo, hi = first + (last - first) // 3, first + 2 * (last - first) // 3
            backwards = ids[::-1]
            window = list(expected.messages(backwards, start_ns=lo, stop_ns=hi))
            assert list(ranged.messages(backwards, start_ns=lo, stop_ns=hi)) == window
    finally:
        expected.close()
        ranged.close()


@pytest.mark.parametrize("relpath", RECORDED)
def test_recorded_bags_read_by_their_index_alone_equal_rosbags(corpus: Path, relpath: str) -> None:
    assert_same(corpus / relpath)


def test_generated_bags_read_by_their_index_alone_equal_rosbags(tmp_path: Path) -> None:
    assert_same(write_bag("ros1", tmp_path))
    assert_same(write_drive_bag("ros1", tmp_path))


class ReadsCounted(HintedFile):
    """A hinted file that records where each read starts."""

    def __init__(self, path: Path) -> None:
        super().__init__(path)
        self.starts: list[int] = []

    def read(self, size: int | None = -1, /) -> bytes:
        self.starts.append(self.tell())
        return super().read(size)


def test_a_stored_objects_compression_reads_three_chunks_not_every_one(tmp_path: Path) -> None:
    """A ranged file fetches a hinted chunk whole when any of it is read, so reading every chunk's header fetched
    the whole bag for filter_bag (1,552 MB of a 2 GB bag); the first, middle and last chunk decide instead."""
    path = write_drive_bag("ros1", tmp_path)
    stream = ReadsCounted(path)
    ranged, local = Ros1RangeSource(path, stream), Ros1Source(path)
    try:
        chunks = stream.hints[0]
        assert len(chunks) > 3  # one chunk is left unread
        stream.starts.clear()
        assert ranged.compression is local.compression
        touched = {chunk for chunk in chunks for at in stream.starts if chunk[0] <= at < chunk[1]}
        assert touched == {chunks[0], chunks[len(chunks) // 2], chunks[-1]}
    finally:
        ranged.close()
        local.close()


@pytest.mark.parametrize(
    ("what", "at", "value"),
    [
        ("a record header longer than the chunk", 0, 0xFFFF_FFF0),  # the first record's header length
        ("a header field longer than its header", 4, 0xFFFF_FFF0),  # its first field's length
        ("a header field without '='", 8, None),  # the first field's name and value, '=' made '-'
        ("a record without an op field", 8, b"op="),  # its op field's name made another
    ],
)
def test_a_chunk_whose_records_do_not_parse_is_damaged_and_named(
    tmp_path: Path, what: str, at: int, value: int | bytes | None
) -> None:
    """A chunk's records are parsed by hand (``message_records``); any record that does not parse ends the read
    in a sentence naming the bag, as rosbags' ``Header`` did."""
    path = write_bag("ros1", tmp_path)  # uncompressed chunks: the records lie in the file as they are
    data = bytearray(path.read_bytes())
    first = Ros1RangeSource(path, io.BytesIO(bytes(data)))._chunks[0].pos
    (header_bytes,) = struct.unpack_from("<I", data, first)
    records = first + 4 + header_bytes + 4
    (header_bytes_of_record,) = struct.unpack_from("<I", data, records)
    header = slice(records + 4, records + 4 + header_bytes_of_record)
    if value is None:
        (size,) = struct.unpack_from("<I", data, records + 4)
        field = records + at
        data[field : field + size] = data[field : field + size].replace(b"=", b"-")
    elif isinstance(value, bytes):
        assert value in data[header]
        data[header] = data[header].replace(value, b"oq=")
    else:
        struct.pack_into("<I", data, records + at, value)
    ranged = Ros1RangeSource(path, io.BytesIO(bytes(data)))
    ids = [c.id for c in ranged.connections]
    with pytest.raises(DamagedBagError, match=rf"{path.name}: a chunk could not be read"):
        list(ranged.messages(ids, start_ns=None, stop_ns=None))


def test_an_index_that_places_a_topic_in_a_chunk_without_it_is_damaged_and_named(tmp_path: Path) -> None:
    """The bounds of a topic come from the first and last chunks the index says hold it; a chunk that holds none
    of its messages is a sentence naming the bag, the chunk and the topic."""
    store = get_typestore(Stores.ROS1_NOETIC)
    path = tmp_path / "idle.bag"
    with Writer(path) as writer:
        talk = writer.add_connection("/talk", STRING, typestore=store)
        writer.add_connection("/idle", STRING, typestore=store)  # no message: in no chunk
        message = store.serialize_ros1(store.types[STRING](data="x"), STRING)
        for second in (1, 2, 3):
            writer.write(talk, second * 10**9, message)
    data = bytearray(path.read_bytes())
    index_at = Ros1RangeSource(path, io.BytesIO(bytes(data)))._index_pos
    at, header, _ = next(r for r in ros1_records(bytes(data), index_at) if header_field(r[1], b"op") == b"\x06")
    struct.pack_into("<I", data, at + 4 + len(header) + 4, 1)  # the chunk info's first pair: /talk's, now /idle's
    ranged = Ros1RangeSource(path, io.BytesIO(bytes(data)))
    with pytest.raises(
        DamagedBagError, match=r"idle\.bag: the index says the chunk at byte 4,109 holds messages of /idle"
    ):
        ranged.bounds(1)


def test_a_bag_whose_index_is_cut_off_is_damaged_and_named(corpus: Path) -> None:
    path = corpus / "edge_cases/ros1_truncated_invalid.bag"
    damaged = r"ros1_truncated_invalid.bag: the ROS 1 bag's index is damaged"
    with path.open("rb") as stream, pytest.raises(DamagedBagError, match=damaged):
        Ros1RangeSource(path, stream)
