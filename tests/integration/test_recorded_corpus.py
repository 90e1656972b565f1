"""Every recording in ../shared/data/bags opens with the documented counts or fails clearly.

Expected counts come from ../shared/data/bags/SOURCES.md (what a good reader should give,
including the talker bags whose metadata.yaml disagrees with their storage files).
"""

from __future__ import annotations

import time
from pathlib import Path

import pytest

from bagmcp_shared.bags import open_bag
from tests.fixtures.corpus_expectations import READABLE, UNREADABLE

pytestmark = pytest.mark.corpus


@pytest.mark.parametrize("relpath", sorted(READABLE))
def test_readable_recording_has_the_documented_topics_and_counts(corpus: Path, relpath: str) -> None:
    with open_bag(corpus / relpath) as bag:
        summary = bag.summary()
    assert {t.name: t.count for t in summary.topics} == READABLE[relpath]
    assert summary.message_count == sum(READABLE[relpath].values())


@pytest.mark.parametrize("relpath", sorted(UNREADABLE))
def test_unreadable_recording_fails_fast_with_a_message_naming_file_and_problem(corpus: Path, relpath: str) -> None:
    error_type, phrase = UNREADABLE[relpath]
    began = time.monotonic()
    with pytest.raises(error_type) as caught:
        open_bag(corpus / relpath).close()
    assert time.monotonic() - began < 5
    message = str(caught.value)
    assert Path(relpath).name in message
    assert phrase in message
    assert "\n" not in message


def test_mcap_without_summary_is_recovered_and_says_so(corpus: Path) -> None:
    with open_bag(corpus / "edge_cases/derived/nav2_turtlebot_no_summary_no_footer.mcap") as bag:
        summary = bag.summary()
        odom = list(bag.messages(["/odom"]))
    assert any("no summary or index" in note and "8197" in note for note in summary.notes)
    assert len(odom) == 2639
    with open_bag(corpus / "ros2_mcap/evo_nav2_turtlebot/nav2_turtlebot.mcap") as indexed:
        assert summary.start_ns == indexed.summary().start_ns
        assert summary.end_ns == indexed.summary().end_ns


def test_talker_bags_read_all_twenty_messages_from_storage_not_metadata(corpus: Path) -> None:
    for relpath in ("ros2_db3/rosbag2_talker", "ros2_mcap/rosbag2_talker"):
        with open_bag(corpus / relpath) as bag:
            texts = [bag.decode(raw).data for raw in bag.messages(["/topic"])]  # type: ignore[attr-defined]
            logs = [bag.decode(raw).msg for raw in bag.messages(["/rosout"])]  # type: ignore[attr-defined]
        assert texts == [f"Hello, world! {i}" for i in range(10)]
        # the sqlite3 bag stores a stub definition of rcl_interfaces/msg/Log; the standard one fits
        assert logs == [f"Publishing: 'Hello, world! {i}'" for i in range(10)]


def test_undecodable_types_are_named_in_the_notes_while_counts_stay_available(corpus: Path) -> None:
    with open_bag(corpus / "edge_cases/ros1_empty_message_definition.bag") as bag:
        notes = bag.summary().notes
    assert notes == (
        "led_array_msgs/msg/Status cannot be decoded: the bag stores no definition and it is not a standard ROS type",
    )


def test_custom_types_in_recordings_decode_from_their_stored_definitions(corpus: Path) -> None:
    with open_bag(corpus / "ros1/datmo_scan_twist_imu/two_robots.bag") as bag:
        ecu = bag.decode(next(bag.messages(["/rc_inputs"])))
    assert type(ecu).__name__ == "barc__msg__ECU"
    assert isinstance(ecu.motor, float)  # type: ignore[attr-defined]
