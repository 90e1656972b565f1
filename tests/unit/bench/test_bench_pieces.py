"""The benchmark's pieces on tiny bags, so the quick path does not rot: the bags it writes, the floors,
the report and the profile summary (nothing timed, no assertion on speed)."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from bagmcp_shared.bags import open_bag
from bench import drive
from bench.bags import BenchBag, bench_bags
from bench.calls import CALLS
from bench.floors import FLOORS, measure_floors, read_topic
from bench.machine import Machine
from bench.measure import CallResult, LoadResult, Overhead
from bench.profile import summarize
from bench.report import render
from bench.results import ModeResult, RunResult
from bench.stats import Timing


@pytest.fixture(scope="module")
def tiny(tmp_path_factory: pytest.TempPathFactory) -> list[BenchBag]:
    return bench_bags(tmp_path_factory.mktemp("bench"), size_gb=0.02)  # 2 s of drive


def test_the_bags_hold_the_drive_at_its_rates_in_every_format(tiny: list[BenchBag]) -> None:
    assert [b.kind for b in tiny] == ["ros1", "ros2-sqlite3", "ros2-mcap"]
    for bag in tiny:
        assert bag.duration_s == 2.0
        with open_bag(bag.path) as reader:
            counts = {t.name: t.count for t in reader.summary().topics}
        assert counts["/odom"] == counts["/tf"] == 201
        assert counts["/scan"] == counts["/camera/image_raw"] == 21
        assert counts["/cmd_vel"] == 41
        assert counts["/rosout"] == 3
        assert bag.size_bytes > 21 * drive.IMAGE_SIDE**2


def test_the_drive_stops_where_it_says_and_the_post_shows_in_the_scan() -> None:
    assert drive.pose_at(0.0) == (0.0, 0.0, 0.0)
    assert drive.arc_m(drive.DRIVING_S + 3.0) == drive.arc_m(drive.DRIVING_S)  # stopped for 5 s
    quarter_s = math.pi / 2 * drive.RADIUS_M / drive.SPEED_MPS  # at the circle's east point
    assert min(drive.scan_ranges(quarter_s)) == pytest.approx(0.5, abs=0.01)  # the post, 0.5 m beside it
    assert min(drive.scan_ranges(0.0)) > 2.5  # the walls are far


def test_every_floor_decodes_messages_of_every_bag(tiny: list[BenchBag]) -> None:
    for bag in tiny:
        floors = measure_floors(bag.path, bag.duration_s, repeats=1)
        assert set(floors) == {f.key for f in FLOORS}
        assert all(len(t) == 1 for t in floors.values())


def test_the_full_decode_floor_decodes_every_message_of_every_topic(tiny: list[BenchBag]) -> None:
    for bag in tiny:
        with open_bag(bag.path) as reader:
            total = sum(t.count for t in reader.summary().topics)
        assert total > 201 + 201 + 21 + 21 + 41 + 3  # the drive's topics, /tf_static too
        assert read_topic(bag.path, None) == total


def _timing(*ms: float) -> Timing:
    return Timing(list(ms))


def test_the_report_shows_targets_met_and_missed_and_the_ratio_to_the_floor(tiny: list[BenchBag]) -> None:
    results = [CallResult(c, cold=_timing(30.0), warm=_timing(5.0, 6.0, 7.0)) for c in CALLS]
    slow = next(r for r in results if r.call.tool == "get_messages_in_range")
    slow.warm = _timing(50.0, 60.0)
    floors: dict[str, dict[str, Timing]] = {b.kind: {f.key: _timing(40.0) for f in FLOORS} for b in tiny}
    mode = ModeResult("embedded", ready_s=1.0, bags={"ros2-mcap": results})
    mode.overhead = [Overhead("bag_info", gateway=_timing(9.0, 10.0), direct=_timing(6.0, 6.5))]
    mode.loads = [LoadResult(20, 30, wall_s=2.0, timing=_timing(*[10.0] * 600))]
    machine = Machine(2, "test cpu", 4.0, "3.11", "linux", "abc")
    page = render(RunResult(machine, False, 3, tiny, floors, [mode]), notes="### Why\n\nbecause")
    assert "| warm bag_info < 20 ms | 11 | 6.0 | met |" in page
    assert "| warm get_messages_in_range 1 s /odom < 20 ms | 11 | 55.0 | **missed** |" in page
    assert "| cold get_message_at_time /odom < 1x floor | 11 | 30.0 (limit 40.0) | met |" in page
    assert "gateway adds < 5 ms median" in page
    assert "300 calls/s" in page
    assert "### Why\n\nbecause" in page


def test_a_profile_is_summed_by_own_time_and_by_project_frames(tmp_path: Path) -> None:
    raw = tmp_path / "raw.txt"
    raw.write_text(
        "main (bagmcp_cli/main.py:1);work (/x/bagmcp_shared/a.py:2);dump (/v/site-packages/pydantic/main.py:3) 30\n"
        "main (bagmcp_cli/main.py:1);work (/x/bagmcp_shared/a.py:2) 10\n"
        "main (bagmcp_cli/main.py:1);wait (/usr/lib/python3.11/threading.py:9);Condition.wait (threading.py:1) 60\n"
    )
    profile = summarize(raw, label="t", process="p")
    assert profile.samples == 40  # waiting threads left out
    assert profile.top_self[0].frame == "dump (pydantic/main.py)"
    assert profile.top_self[0].self_pct == 75.0
    work = next(h for h in profile.top_project if h.frame.startswith("work"))
    assert work.total_pct == 100.0
