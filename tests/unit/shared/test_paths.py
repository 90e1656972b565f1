"""Message paths parse, validate against the type, and extract values (incl. roll/pitch/yaw)."""

from __future__ import annotations

import math

import pytest
from rosbags.typesys import Stores, get_typestore

from bagmcp_shared.errors import MessagePathError
from bagmcp_shared.paths import (
    check_steps,
    extract,
    field_paths,
    parse_field_path,
    parse_message_path,
    quaternion_angles,
)
from tests.fixtures.bagfactory import make

STORE = get_typestore(Stores.ROS2_HUMBLE)
ODOM = "nav_msgs/msg/Odometry"


def test_a_path_splits_into_topic_fields_and_indexes() -> None:
    path = parse_message_path("/scan.ranges[3]")
    assert (path.topic, path.steps) == ("/scan", ("ranges", 3))
    assert str(path) == "/scan.ranges[3]"
    assert parse_message_path("odom.pose.pose.position.x").steps == ("pose", "pose", "position", "x")


def test_a_topic_alone_means_the_whole_message() -> None:
    assert parse_message_path("/tf").steps == ()


@pytest.mark.parametrize("bad", [".x", "/odom..x", "/odom.pose[x]", "/odom.9lives"])
def test_malformed_paths_are_refused(bad: str) -> None:
    with pytest.raises(MessagePathError):
        parse_message_path(bad)


def test_valid_paths_return_the_leaf_type() -> None:
    assert check_steps(STORE, ODOM, parse_field_path("twist.twist.linear.x")) == "float64"
    assert check_steps(STORE, ODOM, parse_field_path("pose.covariance[35]")) == "float64"
    assert check_steps(STORE, ODOM, parse_field_path("pose.pose.orientation.yaw")) == "float64"
    assert check_steps(STORE, "sensor_msgs/msg/LaserScan", ("ranges",)) == "float32[]"


def test_a_wrong_field_lists_the_valid_paths() -> None:
    with pytest.raises(MessagePathError) as caught:
        check_steps(STORE, ODOM, parse_field_path("pose.pos.x"))
    assert "no field 'pos'" in str(caught.value)
    assert "pose.pose.position.x" in str(caught.value)


def test_indexing_a_scalar_is_refused() -> None:
    with pytest.raises(MessagePathError, match="is not an array"):
        check_steps(STORE, ODOM, parse_field_path("child_frame_id[0]"))


def test_field_paths_list_leaves_with_types_and_derived_angles() -> None:
    paths = dict(field_paths(STORE, ODOM))
    assert paths["twist.twist.angular.z"] == "float64"
    assert paths["pose.covariance"] == "float64[36]"
    assert paths["pose.pose.orientation.yaw"].startswith("float64 (derived")
    assert dict(field_paths(STORE, "tf2_msgs/msg/TFMessage"))["transforms[0].child_frame_id"] == "string"


def test_extract_reads_nested_values_indexes_and_yaw() -> None:
    yaw = 0.7
    msg = make(
        STORE,
        ODOM,
        pose={"pose": {"position": {"x": 1.5}, "orientation": {"z": math.sin(yaw / 2), "w": math.cos(yaw / 2)}}},
    )
    assert extract(msg, parse_field_path("pose.pose.position.x")) == 1.5
    assert extract(msg, parse_field_path("pose.pose.orientation.yaw")) == pytest.approx(yaw)
    assert extract(msg, parse_field_path("pose.covariance[2]")) == 0.0


def test_an_index_past_the_end_says_how_many_elements_there_are() -> None:
    scan = make(STORE, "sensor_msgs/msg/LaserScan")
    with pytest.raises(MessagePathError, match="has 0 elements"):
        extract(scan, ("ranges", 3))


def test_quaternion_angles_match_a_known_rotation() -> None:
    half = math.sqrt(0.5)
    angles = quaternion_angles(0.0, 0.0, half, half)
    assert angles["yaw"] == pytest.approx(math.pi / 2)
    assert angles["roll"] == pytest.approx(0.0)
