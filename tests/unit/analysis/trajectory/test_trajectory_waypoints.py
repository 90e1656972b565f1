"""Tests of waypoints: RDP corners, stop-turn-go corners RDP cannot see, and the max_waypoints limit."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from bagmcp_analysis.trajectory.track import Track, summarize_track
from bagmcp_analysis.trajectory.waypoints import rdp_corners, rdp_tolerance_m
from tests.fixtures.synthetic_tracks import phased_track


def _polyline_track(vertices: list[tuple[float, float]], *, step_m: float = 0.01) -> Track:
    """Constant 1 m/s along straight segments through the vertices, one sample per step_m."""
    xs: list[float] = [vertices[0][0]]
    ys: list[float] = [vertices[0][1]]
    for (ax, ay), (bx, by) in itertools.pairwise(vertices):
        steps = round(math.hypot(bx - ax, by - ay) / step_m)
        fraction = np.arange(1, steps + 1) / steps
        xs += (ax + fraction * (bx - ax)).tolist()
        ys += (ay + fraction * (by - ay)).tolist()
    count = len(xs)
    t_ns = np.arange(count, dtype=np.int64) * round(step_m * 1e9)
    return Track(t_ns=t_ns, x=np.array(xs), y=np.array(ys), z=np.zeros(count), yaw=np.full(count, math.nan))


def _positions(track: Track, indices: list[int]) -> list[float]:
    """Flattened x, y of the given samples."""
    return [float(value) for i in indices for value in (track.x[i], track.y[i])]


def _flat(points: list[tuple[float, float]]) -> list[float]:
    return [value for point in points for value in point]


def test_stop_and_full_spin_on_a_straight_line_is_a_stop_waypoint() -> None:
    track = phased_track([(4.0, 0.5, 0.0), (1.0, 0.0, 0.0), (4.0, 0.0, math.pi / 2.0), (4.0, 0.5, 0.0)])
    summary = summarize_track(track)
    assert [w.reason for w in summary.waypoints] == ["start", "stop", "end"]
    assert summary.waypoints[1].index == 80
    assert _positions(track, [w.index for w in summary.waypoints]) == pytest.approx(_flat([(0, 0), (2, 0), (4, 0)]))


def test_spin_in_place_without_a_pause_is_a_corner_waypoint() -> None:
    track = phased_track([(4.0, 0.5, 0.0), (4.0, 0.0, math.pi / 2.0), (4.0, 0.5, 0.0)])
    summary = summarize_track(track)
    assert [(w.index, w.reason) for w in summary.waypoints] == [(0, "start"), (80, "corner"), (240, "end")]


def test_looking_around_in_place_without_changing_course_is_not_a_waypoint() -> None:
    look = math.radians(60.0)
    track = phased_track([(4.0, 0.5, 0.0), (1.0, 0.0, look), (2.0, 0.0, -look), (1.0, 0.0, look), (4.0, 0.5, 0.0)])
    summary = summarize_track(track)
    assert [w.reason for w in summary.waypoints] == ["start", "end"]


def test_rounded_corner_while_driving_is_found_by_rdp() -> None:
    track = _polyline_track([(0.0, 0.0), (3.0, 0.0), (3.0, 3.0)])
    summary = summarize_track(track)
    assert [w.reason for w in summary.waypoints] == ["start", "corner", "end"]
    assert _positions(track, [w.index for w in summary.waypoints]) == pytest.approx(_flat([(0, 0), (3, 0), (3, 3)]))


def test_least_significant_corners_are_dropped_first() -> None:
    vertices = [(0.0, 0.0), (1.0, 0.3), (2.0, 0.0), (3.0, 2.0), (4.0, 0.0), (5.0, 0.0)]
    track = _polyline_track(vertices)
    all_corners = summarize_track(track).waypoints
    assert _positions(track, [w.index for w in all_corners]) == pytest.approx(_flat(vertices))
    limited = summarize_track(track, max_waypoints=3).waypoints
    assert _positions(track, [w.index for w in limited]) == pytest.approx(_flat([(0, 0), (3, 2), (5, 0)]))


def test_rdp_tolerance_is_two_percent_of_the_diagonal_with_a_floor() -> None:
    assert rdp_tolerance_m(np.array([0.0, 30.0]), np.array([0.0, 40.0])) == pytest.approx(1.0)
    assert rdp_tolerance_m(np.array([0.0, 0.3]), np.array([0.0, 0.4])) == pytest.approx(0.05)


def test_rdp_reports_the_deviation_of_each_kept_vertex() -> None:
    x = np.array([0.0, 1.0, 2.0, 3.0, 4.0])
    y = np.array([0.0, 0.0, 1.0, 0.0, 0.0])
    assert rdp_corners(x, y, 0.1) == pytest.approx({2: 1.0, 1: 1.0 / math.sqrt(5.0), 3: 1.0 / math.sqrt(5.0)})


def test_rdp_keeps_the_turnaround_of_a_back_and_forth_drive() -> None:
    x = np.array([0.0, 2.0, 0.0])
    y = np.zeros(3)
    assert rdp_corners(x, y, 0.1) == {1: 2.0}


def test_too_few_waypoints_is_a_user_error() -> None:
    with pytest.raises(ValueError, match="max_waypoints"):
        summarize_track(phased_track([(1.0, 1.0, 0.0)]), max_waypoints=1)
