"""Tests of summarize_track on closed-form paths: square with stops and turns, line, circle, single pose."""

from __future__ import annotations

import math

import numpy as np
import pytest

from bagmcp_analysis.trajectory.track import EARTH_RADIUS_M, Track, pick_clock, summarize_track, track_from_fixes
from tests.fixtures.synthetic_tracks import line_track, phased_track, square_phases


def test_square_drive_reports_distance_speeds_times_and_extents() -> None:
    summary = summarize_track(phased_track(square_phases()))
    assert summary.samples == 26 * 20 + 1
    assert summary.duration_s == pytest.approx(26.0)
    assert summary.distance_2d_m == pytest.approx(8.0, rel=0.01)
    assert summary.distance_3d_m == pytest.approx(8.0, rel=0.01)
    assert summary.displacement_2d_m == pytest.approx(0.0, abs=1e-9)
    assert summary.path_efficiency == pytest.approx(0.0, abs=1e-9)
    assert summary.max_speed_mps == pytest.approx(0.5)
    assert summary.moving_s == pytest.approx(16.0 + 3 * 2.0, abs=0.1)
    assert summary.stopped_s == pytest.approx(4.0, abs=0.1)
    assert summary.moving_s + summary.stopped_s == pytest.approx(summary.duration_s)
    assert summary.mean_speed_mps == pytest.approx(8.0 / 26.0)
    assert summary.mean_moving_speed_mps == pytest.approx(8.0 / 22.0, rel=0.01)
    extents = summary.extents
    assert (extents.min_x, extents.max_x, extents.min_y, extents.max_y) == pytest.approx((0, 2, 0, 2), abs=1e-9)
    assert (extents.min_z, extents.max_z) == (0.0, 0.0)


def test_square_drive_has_four_one_second_stops() -> None:
    summary = summarize_track(phased_track(square_phases()))
    assert [stop.duration_s for stop in summary.stops] == pytest.approx([1.0] * 4, abs=0.1)
    stop_starts_s = [stop.start_index / 20 for stop in summary.stops]
    assert stop_starts_s == pytest.approx([4.0, 11.0, 18.0, 25.0], abs=0.1)


def test_square_drive_waypoints_are_the_four_corners() -> None:
    track = phased_track(square_phases())
    summary = summarize_track(track)
    reasons = [waypoint.reason for waypoint in summary.waypoints]
    assert reasons == ["start", "stop", "stop", "stop", "end"]
    corners = [(track.x[w.index], track.y[w.index]) for w in summary.waypoints]
    expected = [(0, 0), (2, 0), (2, 2), (0, 2), (0, 0)]
    for corner, want in zip(corners, expected, strict=True):
        assert corner == pytest.approx(want, abs=1e-6)


def test_straight_line_has_full_efficiency_and_no_corners() -> None:
    summary = summarize_track(line_track(length_m=10.0, speed_mps=1.0, rate_hz=10))
    assert summary.distance_2d_m == pytest.approx(10.0)
    assert summary.displacement_2d_m == pytest.approx(10.0)
    assert summary.path_efficiency == pytest.approx(1.0)
    assert summary.max_speed_mps == pytest.approx(1.0)
    assert summary.mean_speed_mps == pytest.approx(1.0)
    assert summary.moving_s == pytest.approx(10.0)
    assert summary.stopped_s == pytest.approx(0.0)
    assert summary.stops == []
    assert [(w.index, w.reason) for w in summary.waypoints] == [(0, "start"), (100, "end")]
    assert (summary.start_index, summary.end_index) == (0, 100)


def test_circle_distance_matches_the_circumference() -> None:
    radius_m, count = 3.0, 400
    angle = np.linspace(0.0, 2.0 * math.pi, count + 1)
    track = Track(
        t_ns=np.arange(count + 1, dtype=np.int64) * 100_000_000,
        x=radius_m * np.cos(angle),
        y=radius_m * np.sin(angle),
        z=np.zeros(count + 1),
        yaw=angle + math.pi / 2.0,
    )
    summary = summarize_track(track)
    assert summary.distance_2d_m == pytest.approx(2.0 * math.pi * radius_m, rel=0.01)
    assert summary.distance_2d_m == pytest.approx(2.0 * count * radius_m * math.sin(math.pi / count))
    speed = 2.0 * math.pi * radius_m / (count * 0.1)
    assert summary.max_speed_mps == pytest.approx(speed, rel=0.01)
    assert 3 <= len(summary.waypoints) <= 12
    for waypoint in summary.waypoints:
        assert math.hypot(track.x[waypoint.index], track.y[waypoint.index]) == pytest.approx(radius_m)


def test_single_pose_has_no_speeds() -> None:
    track = Track(t_ns=np.array([5]), x=np.array([1.0]), y=np.array([2.0]), z=np.array([3.0]), yaw=np.array([0.0]))
    summary = summarize_track(track)
    assert (summary.samples, summary.duration_s, summary.distance_2d_m) == (1, 0.0, 0.0)
    assert summary.path_efficiency is None
    assert summary.max_speed_mps is None
    assert summary.mean_speed_mps is None
    assert summary.moving_s == summary.stopped_s == 0.0
    assert [(w.index, w.reason) for w in summary.waypoints] == [(0, "start")]
    assert (summary.extents.min_x, summary.extents.max_y, summary.extents.max_z) == (1.0, 2.0, 3.0)
    assert any("single pose" in note for note in summary.notes)


def test_empty_track_is_a_user_error() -> None:
    empty = np.zeros(0)
    with pytest.raises(ValueError, match="no poses"):
        summarize_track(Track(t_ns=np.zeros(0, dtype=np.int64), x=empty, y=empty, z=empty, yaw=empty))


def test_unknown_altitude_leaves_3d_values_out() -> None:
    line = line_track(length_m=2.0, speed_mps=1.0, rate_hz=10)
    track = Track(t_ns=line.t_ns, x=line.x, y=line.y, z=np.full(line.x.size, np.nan), yaw=line.yaw)
    summary = summarize_track(track)
    assert summary.distance_3d_m is None
    assert summary.displacement_3d_m is None
    assert summary.extents.min_z is None
    assert summary.distance_2d_m == pytest.approx(2.0)


def test_climb_adds_to_3d_distance() -> None:
    line = line_track(length_m=3.0, speed_mps=1.0, rate_hz=10)
    track = Track(t_ns=line.t_ns, x=line.x, y=line.y, z=line.x * (4.0 / 3.0), yaw=line.yaw)
    summary = summarize_track(track)
    assert summary.distance_3d_m == pytest.approx(5.0)
    assert summary.displacement_3d_m == pytest.approx(5.0)


def test_header_stamps_are_used_when_positive_and_monotonic() -> None:
    log_ns = np.array([10, 20, 30], dtype=np.int64)
    t_ns, clock, note = pick_clock(log_ns, np.array([5, 5, 25], dtype=np.int64))
    assert (t_ns.tolist(), clock, note) == ([5, 5, 25], "header", None)


@pytest.mark.parametrize(
    ("header", "reason"),
    [([1, 0, 3], "1 of 3 header stamps are zero or negative"), ([5, 4, 6], "go backwards 1 times")],
)
def test_bad_header_stamps_fall_back_to_log_time_with_a_note(header: list[int], reason: str) -> None:
    log_ns = np.array([10, 20, 30], dtype=np.int64)
    t_ns, clock, note = pick_clock(log_ns, np.array(header, dtype=np.int64))
    assert (t_ns.tolist(), clock) == ([10, 20, 30], "log_time")
    assert note is not None
    assert reason in note


def test_missing_header_stamps_fall_back_to_log_time() -> None:
    _, clock, note = pick_clock(np.array([1, 2], dtype=np.int64), None)
    assert clock == "log_time"
    assert note is not None


def test_a_thousandth_of_a_degree_north_is_111_metres() -> None:
    track = track_from_fixes(
        np.array([0, 1, 2, 3], dtype=np.int64),
        np.array([48.0, 48.0005, math.nan, 48.001]),
        np.array([11.0, 11.0, 11.0, 11.0]),
        np.array([500.0, 501.0, 502.0, 497.0]),
        np.array([0, -1, 0, 2], dtype=np.int64),
    )
    metres_per_degree = EARTH_RADIUS_M * math.pi / 180.0
    assert track.t_ns.tolist() == [0, 3]
    assert track.y.tolist() == pytest.approx([0.0, 0.001 * metres_per_degree])
    assert track.y[1] == pytest.approx(111.2, abs=0.05)
    assert track.x.tolist() == pytest.approx([0.0, 0.0])
    assert track.z.tolist() == pytest.approx([0.0, -3.0])
    assert np.isnan(track.yaw).all()


def test_east_offsets_shrink_with_the_cosine_of_latitude() -> None:
    track = track_from_fixes(
        np.array([0, 1], dtype=np.int64),
        np.array([60.0, 60.0]),
        np.array([179.9995, -179.9995]),
        np.array([0.0, 0.0]),
        np.array([0, 0], dtype=np.int64),
    )
    assert track.x[1] == pytest.approx(0.001 * EARTH_RADIUS_M * math.pi / 180.0 * 0.5)
    summary = summarize_track(track)
    assert summary.distance_2d_m == pytest.approx(55.6, abs=0.05)
    assert any("Heading is unknown" in note for note in summary.notes)


def test_no_valid_fix_is_a_user_error() -> None:
    one = np.array([0], dtype=np.int64)
    with pytest.raises(ValueError, match="No valid GPS fix"):
        track_from_fixes(one, np.array([48.0]), np.array([11.0]), np.array([0.0]), np.array([-1]))
