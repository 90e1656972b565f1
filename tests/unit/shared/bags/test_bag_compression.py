"""The reader knows how a bag is compressed: ROS 1 and MCAP chunk compression, rosbag2's
compression_mode, and none for plain bags."""

from __future__ import annotations

from pathlib import Path

import pytest

from bagmcp_shared.bags import Compression, open_bag
from tests.fixtures.bagfactory import BagKind
from tests.fixtures.compressed_bags import COMPRESSED_KINDS, COMPRESSION_OF, CompressedKind


@pytest.mark.parametrize("kind", COMPRESSED_KINDS)
def test_the_reader_reports_the_compression_a_bag_was_written_with(
    compressed_bags: dict[CompressedKind, Path], kind: CompressedKind
) -> None:
    with open_bag(compressed_bags[kind]) as bag:
        assert bag.compression is COMPRESSION_OF[kind]


def test_uncompressed_bags_report_none(scenario_bags: dict[BagKind, Path]) -> None:
    for path in scenario_bags.values():
        with open_bag(path) as bag:
            assert bag.compression is Compression.NONE, path.name


REAL = [
    ("ros1/turtlesim_rosbagjs/example.bag", Compression.NONE),
    ("ros1/turtlesim_rosbagjs/example-bz2.bag", Compression.BZ2),
    ("ros1/turtlesim_rosbagjs/example-lz4.bag", Compression.LZ4),
    ("ros1/husky_gps_imu_odom/test1.bag", Compression.BZ2),
    ("ros1/rosout_log/out.bag", Compression.LZ4),
    ("edge_cases/ros1_no_messages.bag", Compression.NONE),
    ("ros2_mcap/rosbag2_talker", Compression.ZSTD),
    ("ros2_mcap/rosbag2_cdr_test", Compression.NONE),
    ("ros2_mcap/rosbag2_wbag_split", Compression.ZSTD),
    ("ros2_mcap/evo_nav2_turtlebot/nav2_turtlebot.mcap", Compression.ZSTD),
    ("edge_cases/derived/nav2_turtlebot_no_summary_no_footer.mcap", Compression.ZSTD),  # read by scanning
    ("ros2_db3/rosbag2_talker", Compression.NONE),
]


@pytest.mark.corpus
@pytest.mark.parametrize(("relative", "expected"), REAL)
def test_real_recordings_report_their_compression(corpus: Path, relative: str, expected: Compression) -> None:
    with open_bag(corpus / relative) as bag:
        assert bag.compression is expected


def test_the_compression_most_chunks_use_wins() -> None:
    assert Compression.of_chunks([]) is Compression.NONE
    assert Compression.of_chunks(["", "none", ""]) is Compression.NONE
    assert Compression.of_chunks(["", "zstd", ""]) is Compression.ZSTD
    assert Compression.of_chunks(["lz4", "bz2", "bz2"]) is Compression.BZ2
    assert Compression.of_chunks(["lz4", "bz2"]) is Compression.BZ2  # a tie goes to the first name
    assert Compression.of_chunks(["brotli", "none"]) is Compression.NONE


def test_each_compression_reads_well_in_a_sentence() -> None:
    labels = {c: c.label for c in Compression}
    assert labels == {
        Compression.NONE: "no compression",
        Compression.BZ2: "bz2 chunks",
        Compression.LZ4: "lz4 chunks",
        Compression.ZSTD: "zstd chunks",
        Compression.ZSTD_FILE: "zstd per storage file",
        Compression.ZSTD_MESSAGE: "zstd per message",
    }
