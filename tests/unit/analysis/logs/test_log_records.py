"""Tests of log records: conversion from messages, filters and summaries for ROS 1 and ROS 2 numbering."""

from __future__ import annotations

from dataclasses import dataclass

import pytest

from bagmcp_analysis.logs.records import LogRecord, filter_records, record_from_message, summarize_records

SECOND_NS = 1_000_000_000
ROS1 = {"DEBUG": 1, "INFO": 2, "WARN": 4, "ERROR": 8, "FATAL": 16}
ROS2 = {"DEBUG": 10, "INFO": 20, "WARN": 30, "ERROR": 40, "FATAL": 50}


@dataclass
class FakeLog:
    """Stand-in for a decoded rosgraph_msgs/Log or rcl_interfaces/msg/Log."""

    level: int
    name: str
    msg: str
    file: str = "planner.cpp"
    function: str = "plan"
    line: int = 42


# (seconds, level, node, text): 3 DEBUG, 5 INFO, 2 WARN, 3 ERROR, 1 FATAL
SCRIPT = [
    (0.0, "INFO", "/planner", "starting"),
    (0.5, "DEBUG", "/planner", "tick"),
    (1.0, "INFO", "/controller", "ready"),
    (2.0, "WARN", "/controller", "Slow loop"),
    (3.0, "ERROR", "/planner", "No path found"),
    (3.5, "DEBUG", "/planner", "tick"),
    (4.0, "INFO", "/planner_server", "replanning"),
    (5.0, "ERROR", "/planner_server", "no PATH again"),
    (6.0, "WARN", "/localizer", "covariance high"),
    (7.0, "INFO", "/planner", "path ok"),
    (8.0, "DEBUG", "/localizer", "tick"),
    (9.0, "FATAL", "/controller", "motor fault"),
    (9.5, "INFO", "/controller", "shutting down"),
    (10.0, "ERROR", "/controller", "stopped"),
]


def _records(*, ros2: bool) -> list[LogRecord]:
    numbers = ROS2 if ros2 else ROS1
    return [
        record_from_message(FakeLog(numbers[level], node, text), round(t_s * SECOND_NS), ros2=ros2)
        for t_s, level, node, text in SCRIPT
    ]


@pytest.mark.parametrize("ros2", [False, True])
def test_record_from_message_reads_every_field(ros2: bool) -> None:
    message = FakeLog(level=(ROS2 if ros2 else ROS1)["WARN"], name="/nav", msg="low battery", line=7)
    record = record_from_message(message, 123, ros2=ros2)
    assert record == LogRecord(123, "WARN", 30 if ros2 else 4, "/nav", "low battery", "planner.cpp", "plan", 7)


def test_message_without_a_level_is_a_user_error() -> None:
    with pytest.raises(ValueError, match="no 'level' field"):
        record_from_message(object(), 0, ros2=True)


@pytest.mark.parametrize("ros2", [False, True])
def test_summary_counts_levels_and_nodes(ros2: bool) -> None:
    summary = summarize_records(_records(ros2=ros2), max_items=3)
    assert summary.total == 14
    assert summary.by_level == {"DEBUG": 3, "INFO": 5, "WARN": 2, "ERROR": 3, "FATAL": 1}
    assert list(summary.by_node.items()) == [("/controller", 5), ("/planner", 5), ("/localizer", 2)]
    assert summary.first_error is not None
    assert summary.last_error is not None
    assert summary.first_warning is not None
    assert (summary.first_error.text, summary.last_error.text) == ("No path found", "stopped")
    assert summary.first_warning.text == "Slow loop"
    assert summary.bursts == []


def test_summary_of_no_records_has_all_levels_at_zero() -> None:
    summary = summarize_records([])
    assert summary.by_level == dict.fromkeys(("DEBUG", "INFO", "WARN", "ERROR", "FATAL"), 0)
    assert (summary.total, summary.by_node, summary.first_error, summary.first_warning) == (0, {}, None, None)


def test_first_and_last_error_follow_time_not_input_order() -> None:
    records = list(reversed(_records(ros2=True)))
    summary = summarize_records(records)
    assert summary.first_error is not None
    assert summary.last_error is not None
    assert (summary.first_error.t_ns, summary.last_error.t_ns) == (3 * SECOND_NS, 10 * SECOND_NS)


@pytest.mark.parametrize("ros2", [False, True])
def test_filter_by_level_and_min_level(ros2: bool) -> None:
    records = _records(ros2=ros2)
    assert len(filter_records(records, level="error")) == 3
    assert len(filter_records(records, level=8 if not ros2 else 40)) == 3
    assert len(filter_records(records, min_level="WARNING")) == 6
    assert [r.text for r in filter_records(records, min_level="fatal")] == ["motor fault"]


def test_node_filter_prefers_an_exact_name_and_ignores_the_leading_slash() -> None:
    records = _records(ros2=True)
    assert len(filter_records(records, node="planner")) == 5
    assert len(filter_records(records, node="/planner_server")) == 2


def test_node_filter_falls_back_to_a_substring_when_no_node_has_that_name() -> None:
    records = _records(ros2=True)
    assert len(filter_records(records, node="plan")) == 7
    assert len(filter_records(records, node="LOCAL")) == 2


def test_text_and_time_window_filters_are_inclusive_and_case_insensitive() -> None:
    records = _records(ros2=True)
    assert [r.t_ns // SECOND_NS for r in filter_records(records, contains="no path")] == [3, 5]
    window = filter_records(records, start_ns=3 * SECOND_NS, end_ns=5 * SECOND_NS)
    assert [r.text for r in window] == ["No path found", "tick", "replanning", "no PATH again"]
    both = filter_records(records, min_level="ERROR", node="planner", contains="path")
    assert [r.text for r in both] == ["No path found"]


def test_bursts_merge_overlapping_windows_and_rank_by_intensity() -> None:
    def flood(start_s: float, count: int, spacing_s: float, node: str, level: int) -> list[LogRecord]:
        return [
            LogRecord(round((start_s + i * spacing_s) * SECOND_NS), "", level, node, "x", "", "", 0)
            for i in range(count)
        ]

    slow = flood(10.0, 30, 0.08, "/lidar", 30)  # 30 records over 2.32 s, any 1 s window holds 13
    fast = flood(50.0, 20, 0.01, "/camera", 40)  # 20 records in 0.19 s
    quiet = flood(100.0, 9, 0.05, "/imu", 20)  # too few for a burst
    records = [
        LogRecord(r.t_ns, lvl, r.level_raw, r.node, r.text, "", "", 0)
        for group, lvl in ((slow, "WARN"), (fast, "ERROR"), (quiet, "INFO"))
        for r in group
    ]
    bursts = summarize_records(records).bursts
    assert [(b.count, b.top_node, b.worst_level) for b in bursts] == [(20, "/camera", "ERROR"), (30, "/lidar", "WARN")]
    assert (bursts[1].start_ns, bursts[1].end_ns) == (10 * SECOND_NS, round(12.32 * SECOND_NS))
    assert len(summarize_records(records, max_items=1).bursts) == 1
    assert [b.count for b in summarize_records(records, burst_min=14).bursts] == [20]
