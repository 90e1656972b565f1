"""Tests for LaserScan geometry: a synthetic room, return classification, sectors and free gaps."""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt
import pytest

from bagmcp_analysis.lidar.scan import scan_stats
from bagmcp_shared.laser_ranges import LaserRanges

# Room 6 m (x) by 4 m (y) around the robot at the origin, facing +x.
X_BACK, X_FRONT, Y_RIGHT, Y_LEFT = -2.0, 4.0, -1.5, 2.5
HALL_WALL_X = 8.0  # a doorway in the front wall (|y| <= 0.5) opens onto a hall whose far wall is at x = 8
POST_RANGE, POST_BEARING_DEG, POST_RADIUS = 1.0, 30.0, 0.1


def room_range(theta: float) -> float:
    """Closed-form range along bearing theta (radians) in the room with two doorways and a round post."""
    c, s = math.cos(theta), math.sin(theta)
    hits: list[tuple[float, str]] = []
    if c > 1e-12:
        hits.append((X_FRONT / c, "front"))
    if c < -1e-12:
        hits.append((X_BACK / c, "back"))
    if s > 1e-12:
        hits.append((Y_LEFT / s, "left"))
    if s < -1e-12:
        hits.append((Y_RIGHT / s, "right"))
    wall_m, wall = min(hits)
    if wall == "left" and abs(wall_m * c) <= 0.5:
        wall_m = math.inf  # left doorway: nothing within range beyond it
    if wall == "front" and abs(wall_m * s) <= 0.5:
        wall_m = HALL_WALL_X / c
    offset = theta - math.radians(POST_BEARING_DEG)
    across = POST_RANGE * math.sin(offset)
    if math.cos(offset) > 0 and abs(across) <= POST_RADIUS:
        wall_m = min(wall_m, POST_RANGE * math.cos(offset) - math.sqrt(POST_RADIUS**2 - across**2))
    return wall_m


def room_scan() -> LaserRanges:
    increment = 2 * math.pi / 360
    ranges = np.array([room_range(-math.pi + i * increment) for i in range(360)], dtype=np.float64)
    return LaserRanges(ranges=ranges, angle_min=-math.pi, angle_increment=increment, range_min=0.05, range_max=10.0)


def test_room_closest_hit_is_the_post_at_its_bearing() -> None:
    stats = scan_stats(room_scan(), free_range_m=5.0)
    assert stats.closest is not None
    assert stats.closest.range_m == pytest.approx(POST_RANGE - POST_RADIUS, abs=1e-9)
    assert stats.closest.bearing_deg == pytest.approx(POST_BEARING_DEG, abs=1e-9)
    assert stats.closest.index == 210
    assert (stats.beams, stats.valid, stats.pos_inf) == (360, 360 - 23, 23)
    assert stats.min_m == pytest.approx(0.9, abs=1e-9)
    assert stats.max_m == pytest.approx(HALL_WALL_X / math.cos(math.radians(7)), abs=1e-9)


def test_room_sector_minima_match_the_walls() -> None:
    stats = scan_stats(room_scan(), free_range_m=5.0)
    by_name = {sector.name: sector for sector in stats.sectors}
    deg = math.radians
    expected = {
        "front": (-Y_RIGHT / math.sin(deg(22)), -22.0),  # the right wall beats the front wall at 4/cos(8°)
        "front-left": (0.9, 30.0),
        "left": (Y_LEFT / math.sin(deg(78)), 78.0),
        "back-left": (-X_BACK / math.cos(deg(23)), 157.0),
        "back": (2.0, 180.0),
        "back-right": (-Y_RIGHT / math.sin(deg(113)), -113.0),
        "right": (1.5, -90.0),
        "front-right": (-Y_RIGHT / math.sin(deg(67)), -67.0),
    }
    for name, (closest_m, bearing_deg) in expected.items():
        sector = by_name[name]
        assert sector.closest_m == pytest.approx(closest_m, abs=1e-9), name
        assert sector.closest_bearing_deg is not None
        assert abs(sector.closest_bearing_deg) == pytest.approx(abs(bearing_deg), abs=1e-9), name
    assert by_name["left"].valid == 45 - 23
    assert all(s.valid == 45 for s in stats.sectors if s.name != "left")


def test_eight_sectors_are_named_and_centred_counter_clockwise() -> None:
    stats = scan_stats(room_scan())
    names = [s.name for s in stats.sectors]
    assert names == ["front", "front-left", "left", "back-left", "back", "back-right", "right", "front-right"]
    assert [s.center_deg for s in stats.sectors] == [0.0, 45.0, 90.0, 135.0, 180.0, -135.0, -90.0, -45.0]
    back = stats.sectors[4]
    assert (back.from_deg, back.to_deg) == (157.5, -157.5)
    assert [s.name for s in scan_stats(room_scan(), sectors=4).sectors] == [f"sector {k}" for k in range(4)]


def test_free_gaps_open_behind_the_doorways_widest_first() -> None:
    for free_range_m in (5.0, None):  # None: default 0.8 * range_max = 8 m, the hall wall still counts
        gaps = scan_stats(room_scan(), free_range_m=free_range_m).free_gaps
        assert len(gaps) == 2
        left, front = gaps
        assert (left.from_deg, left.to_deg) == pytest.approx((79.0, 101.0))
        assert left.width_deg == pytest.approx(22.0)
        assert left.nearest_m is None
        assert (front.from_deg, front.to_deg) == pytest.approx((-7.0, 7.0))
        assert front.width_deg == pytest.approx(14.0)
        assert front.nearest_m == pytest.approx(HALL_WALL_X, abs=1e-9)


def test_invalid_returns_are_counted_by_kind() -> None:
    ranges = np.array([np.nan, np.inf, -np.inf, 0.05, 12.0, 1.0, 2.0, 3.0, np.nan, 0.1, 10.0])
    scan = LaserRanges(ranges=ranges, angle_min=0.0, angle_increment=0.1, range_min=0.1, range_max=10.0)
    stats = scan_stats(scan, free_range_m=2.5, max_gaps=2)
    counts = (stats.nan, stats.pos_inf, stats.neg_inf, stats.below_min, stats.above_max, stats.valid)
    assert counts == (2, 1, 1, 1, 1, 5)
    assert (stats.min_m, stats.max_m, stats.median_m) == (0.1, 10.0, 2.0)
    assert stats.mean_m == pytest.approx((1.0 + 2.0 + 3.0 + 0.1 + 10.0) / 5)
    assert stats.closest is not None
    assert (stats.closest.index, stats.closest.range_m) == (9, 0.1)
    assert stats.closest.bearing_deg == pytest.approx(math.degrees(0.9))
    # free beams: +inf (1), 12 m beyond range_max (4), 3 m (7) and 10 m (10); widest first, ties by index
    assert [(round(g.from_deg, 6), g.nearest_m) for g in stats.free_gaps] == [
        (round(math.degrees(0.1), 6), None),
        (round(math.degrees(0.4), 6), None),
    ]


def test_scan_without_valid_beams_reports_none() -> None:
    scan = LaserRanges(ranges=np.full(5, np.nan), angle_min=0.0, angle_increment=0.1, range_min=0.1, range_max=5.0)
    stats = scan_stats(scan)
    assert (stats.valid, stats.min_m, stats.median_m, stats.closest, stats.free_gaps) == (0, None, None, None, [])
    assert all(s.valid == 0 and s.closest_m is None for s in stats.sectors)


def _ring(free_bearings_deg: set[int], *, first_deg: int, beams: int, step: float = 1.0) -> LaserRanges:
    bearings = [first_deg + step * i for i in range(beams)]
    ranges: npt.NDArray[np.float64] = np.array(
        [np.inf if round(b) % 360 in {f % 360 for f in free_bearings_deg} else 1.0 for b in bearings]
    )
    return LaserRanges(
        ranges=ranges,
        angle_min=math.radians(first_deg),
        angle_increment=math.radians(step),
        range_min=0.1,
        range_max=5.0,
    )


def test_gap_across_the_seam_of_a_full_scan_is_joined() -> None:
    behind = set(range(170, 191))  # 170..179 and -180..-170
    gaps = scan_stats(_ring(behind, first_deg=-180, beams=360)).free_gaps
    assert len(gaps) == 1
    assert (gaps[0].from_deg, gaps[0].to_deg) == pytest.approx((170.0, -170.0))
    assert gaps[0].width_deg == pytest.approx(20.0)


def test_gap_at_both_ends_of_a_partial_scan_is_not_joined() -> None:
    ends = set(range(-135, -129)) | set(range(130, 136))
    gaps = scan_stats(_ring(ends, first_deg=-135, beams=271)).free_gaps
    assert sorted((round(g.from_deg), round(g.to_deg)) for g in gaps) == [(-135, -130), (130, 135)]


def test_clockwise_scan_reports_gaps_counter_clockwise() -> None:
    scan = _ring(set(range(10, 21)), first_deg=90, beams=181, step=-1.0)
    gaps = scan_stats(scan).free_gaps
    assert [(round(g.from_deg), round(g.to_deg), round(g.width_deg)) for g in gaps] == [(10, 20, 10)]


def test_zero_angle_increment_is_rejected() -> None:
    scan = LaserRanges(ranges=np.ones(3), angle_min=0.0, angle_increment=0.0, range_min=0.1, range_max=5.0)
    with pytest.raises(ValueError, match="angle_increment"):
        scan_stats(scan)
