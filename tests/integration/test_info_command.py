"""``bagmcp info`` as a user runs it: the installed command, real bags, real exit codes."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from tests.fixtures import scenario as sc
from tests.fixtures.corpus_expectations import READABLE, UNREADABLE


def _bagmcp(*args: str) -> subprocess.CompletedProcess[str]:
    exe = shutil.which("bagmcp", path=str(Path(sys.executable).parent))
    command = [exe] if exe else [sys.executable, "-m", "bagmcp_gateway"]
    return subprocess.run([*command, *args], capture_output=True, text=True, timeout=60, check=False)


def test_info_json_reports_counts_duration_and_topics_of_a_generated_bag(scenario_bag: Path) -> None:
    result = _bagmcp("info", "--json", str(scenario_bag))
    assert result.returncode == 0, result.stderr
    info = json.loads(result.stdout)
    assert info["message_count"] == sum(sc.COUNTS.values())
    assert info["duration_s"] == pytest.approx(sc.DURATION_S - 1 / sc.ODOM_HZ)
    assert {t["name"]: (t["type"], t["count"]) for t in info["topics"]}[sc.ODOM_TOPIC] == (
        "nav_msgs/msg/Odometry",
        sc.COUNTS[sc.ODOM_TOPIC],
    )
    assert info["start_ns"] == sc.START_NS


def test_info_text_names_format_and_topics(scenario_bag: Path) -> None:
    result = _bagmcp("info", str(scenario_bag))
    assert result.returncode == 0, result.stderr
    assert "Messages:  595" in result.stdout
    assert "/odom" in result.stdout
    assert "20.00 Hz" in result.stdout


# One recording per kind of reader: the installed command on each (a process costs about 1.5 s of CPU; every
# readable recording's counts are checked in process by test_recorded_corpus.py).
ONE_OF_EACH_KIND = [
    "ros1/turtlesim_rosbagjs/example-lz4.bag",
    "ros2_db3/plotjuggler_imu_pose_battery",
    "ros2_mcap/rosbag2_wbag_split",
    "ros2_mcap/evo_nav2_turtlebot/nav2_turtlebot.mcap",
    "edge_cases/mcap_non_ros_profile_data_tamer.mcap",
    "edge_cases/ros2_no_metadata_split_db3",
]


@pytest.mark.corpus
def test_info_json_counts_match_the_corpus_for_each_kind_of_recording(corpus: Path) -> None:
    for relpath in ONE_OF_EACH_KIND:
        topics = READABLE[relpath]
        result = _bagmcp("info", "--json", str(corpus / relpath))
        assert result.returncode == 0, f"{relpath}: {result.stderr}"
        info = json.loads(result.stdout)
        assert {t["name"]: t["count"] for t in info["topics"]} == topics, relpath
        assert info["message_count"] == sum(topics.values())


@pytest.mark.corpus
@pytest.mark.parametrize("relpath", sorted(UNREADABLE))
def test_info_on_a_damaged_file_exits_nonzero_with_one_clear_line(corpus: Path, relpath: str) -> None:
    result = _bagmcp("info", "--json", str(corpus / relpath))
    assert result.returncode == 1
    assert result.stdout == ""
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1
    assert lines[0].startswith("bagmcp: error: ")
    assert Path(relpath).name in lines[0]
    assert "Traceback" not in result.stderr


def test_info_on_a_missing_path_says_so(tmp_path: Path) -> None:
    result = _bagmcp("info", str(tmp_path / "nope.bag"))
    assert result.returncode == 1
    assert "no such file or directory" in result.stderr
