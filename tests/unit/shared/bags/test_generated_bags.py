"""The three generated formats read back exactly what was written (see fixtures/scenario.py)."""

from __future__ import annotations

import sqlite3
from pathlib import Path

import pytest

from bagmcp_shared.bags import open_bag
from bagmcp_shared.bags.sqlite3_source import file_key, topic_stats
from bagmcp_shared.errors import TopicNotFoundError
from bagmcp_shared.paths import extract, parse_field_path
from tests.fixtures import scenario as sc
from tests.fixtures.bagfactory import BagKind


def test_summary_has_every_topic_with_its_count_and_rate(scenario_bag: Path) -> None:
    with open_bag(scenario_bag) as bag:
        summary = bag.summary()
    assert {t.name: t.count for t in summary.topics} == sc.COUNTS
    assert summary.start_ns == sc.START_NS
    assert summary.end_ns == sc.stamp_ns(sc.DURATION_S - 1 / sc.ODOM_HZ)
    odom = summary.topic("odom")
    assert odom is not None
    assert odom.rate_hz == pytest.approx(sc.ODOM_HZ)
    assert summary.notes == ()


def test_a_time_window_on_one_topic_yields_exactly_that_slice(scenario_bag: Path) -> None:
    with open_bag(scenario_bag) as bag:
        raws = list(bag.messages(["/cmd_vel"], start_ns=sc.stamp_ns(2.0), stop_ns=sc.stamp_ns(3.0)))
        speeds = [extract(bag.decode(r), parse_field_path("linear.x")) for r in raws]
    assert [r.log_time_ns for r in raws] == [sc.stamp_ns(2.0 + i / 10) for i in range(10)]
    assert {r.connection.topic for r in raws} == {"/cmd_vel"}
    assert speeds == pytest.approx([sc.cmd_speed_at(2.0)] * 10)


def test_messages_of_several_topics_come_in_time_order(scenario_bag: Path) -> None:
    with open_bag(scenario_bag) as bag:
        times = [r.log_time_ns for r in bag.messages(["/odom", "/scan", "/rosout"])]
    assert times == sorted(times)
    assert len(times) == sc.COUNTS["/odom"] + sc.COUNTS["/scan"] + sc.COUNTS["/rosout"]


def test_the_custom_type_decodes_from_the_definition_in_the_bag(scenario_bag: Path) -> None:
    with open_bag(scenario_bag) as bag:
        first = bag.decode(next(bag.messages([sc.BATTERY_TOPIC])))
    assert extract(first, ("label",)) == "pack-0"
    assert list(extract(first, ("cell_mv",))) == [3700, 3710]  # type: ignore[call-overload]


def test_odometry_positions_follow_the_scenario_circle(scenario_bag: Path) -> None:
    with open_bag(scenario_bag) as bag:
        raw = next(bag.messages(["/odom"], start_ns=sc.stamp_ns(5.0)))
        msg = bag.decode(raw)
    x, y, yaw = sc.pose_at(5.0)
    assert extract(msg, parse_field_path("pose.pose.position.x")) == pytest.approx(x)
    assert extract(msg, parse_field_path("pose.pose.position.y")) == pytest.approx(y)
    assert extract(msg, parse_field_path("pose.pose.orientation.yaw")) == pytest.approx(yaw)


def test_an_unknown_topic_lists_the_topics_that_exist(scenario_bag: Path) -> None:
    with open_bag(scenario_bag) as bag, pytest.raises(TopicNotFoundError) as caught:
        list(bag.messages(["/odometry"]))
    assert "/odom" in str(caught.value)
    assert "/cmd_vel" in str(caught.value)


def test_topics_match_with_or_without_the_leading_slash(scenario_bag: Path) -> None:
    with open_bag(scenario_bag) as bag:
        assert len(list(bag.messages(["scan"]))) == sc.COUNTS["/scan"]


def test_sqlite3_topic_statistics_are_scanned_once_per_file_content(scenario_bags: dict[BagKind, Path]) -> None:
    storage = next(scenario_bags["ros2-sqlite3"].glob("*.db3"))
    db = sqlite3.connect(f"{storage.resolve().as_uri()}?mode=ro&immutable=1", uri=True)
    scans: list[str] = []
    db.set_trace_callback(lambda statement: scans.append(statement) if "GROUP BY" in statement else None)
    first = topic_stats(db, file_key(storage))
    again = topic_stats(db, file_key(storage))
    db.close()
    assert again is first
    assert len(scans) <= 1  # zero when an earlier test already opened this file
    assert sum(count for count, _, _ in first.values()) == sum(sc.COUNTS.values())
