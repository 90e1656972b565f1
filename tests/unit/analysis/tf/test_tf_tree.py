"""Tests for the TF buffer: tree summary and tf2-style lookups checked against homogeneous matrices."""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt
import pytest

from bagmcp_analysis.tf.quaternions import from_rpy
from bagmcp_analysis.tf.tree import Lookup, TfBuffer, TfSample, normalize_frame

S = 1_000_000_000
Matrix = npt.NDArray[np.float64]


def rot_z(angle: float) -> Matrix:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def rot_x(angle: float) -> Matrix:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def pose(translation: tuple[float, float, float], rotation: Matrix) -> Matrix:
    m = np.eye(4)
    m[:3, :3] = rotation
    m[:3, 3] = translation
    return m


def lookup_matrix(lookup: Lookup) -> Matrix:
    """Homogeneous matrix of a lookup, using the textbook quaternion-to-matrix formula."""
    x, y, z, w = lookup.rotation
    rotation = np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )
    return pose(lookup.translation, rotation)


MAP_ODOM = pose((1.0, 2.0, 0.0), rot_z(math.pi / 2))
BASE_LASER = pose((0.2, 0.0, 0.3), rot_z(0.3) @ rot_x(math.pi))  # upside-down laser, yawed 0.3 rad
ODOM_BASE = {0: ((0.0, 0.0, 0.0), 0.0), 1: ((2.0, 0.0, 0.0), math.pi / 2), 2: ((2.0, 2.0, 0.0), math.pi)}


def samples() -> list[TfSample]:
    out = [
        TfSample(0, "/map", "odom", (1.0, 2.0, 0.0), from_rpy(0.0, 0.0, math.pi / 2), static=True),
        TfSample(0, "base_link", "/laser", (0.2, 0.0, 0.3), from_rpy(math.pi, 0.0, 0.3), static=True),
        TfSample(0, "base_link", "imu", (0.0, 0.1, 0.0), from_rpy(0.0, 0.0, 0.0), static=True),
    ]
    for second, (translation, yaw) in ODOM_BASE.items():
        out.append(TfSample(second * S, "odom", "base_link", translation, from_rpy(0.0, 0.0, yaw), static=False))
    return out


def test_map_to_laser_matches_the_hand_composed_chain() -> None:
    lookup = TfBuffer(samples()).lookup("map", "laser", 1 * S)
    expected = MAP_ODOM @ pose((2.0, 0.0, 0.0), rot_z(math.pi / 2)) @ BASE_LASER
    assert np.allclose(lookup_matrix(lookup), expected, atol=1e-6)
    assert lookup.translation == pytest.approx((0.8, 4.0, 0.3), abs=1e-6)  # laser at (2, 0.2, 0.3) in odom
    assert lookup.chain == ["laser", "base_link", "odom", "map"]
    assert abs(lookup.roll_rad) == pytest.approx(math.pi, abs=1e-6)
    assert lookup.pitch_rad == pytest.approx(0.0, abs=1e-6)
    assert lookup.yaw_rad == pytest.approx(0.3 - math.pi, abs=1e-6)
    assert lookup.rotation[3] >= 0
    assert (lookup.interpolated, lookup.extrapolated_s) == (False, 0.0)


def test_inverse_lookup_composes_to_identity() -> None:
    buffer = TfBuffer(samples())
    forward = buffer.lookup("map", "laser", 3 * S // 2)
    backward = buffer.lookup("laser", "map", 3 * S // 2)
    assert np.allclose(lookup_matrix(forward) @ lookup_matrix(backward), np.eye(4), atol=1e-6)
    assert backward.chain == ["map", "odom", "base_link", "laser"]


def test_halfway_between_pure_yaw_samples_gives_half_angle_and_midpoint() -> None:
    buffer = TfBuffer(samples())
    early = buffer.lookup("odom", "base_link", S // 2)
    assert early.yaw_rad == pytest.approx(math.pi / 4, abs=1e-6)
    assert early.translation == pytest.approx((1.0, 0.0, 0.0), abs=1e-6)
    late = buffer.lookup("odom", "base_link", 3 * S // 2)
    assert late.yaw_rad == pytest.approx(3 * math.pi / 4, abs=1e-6)
    assert late.translation == pytest.approx((2.0, 1.0, 0.0), abs=1e-6)
    assert (late.interpolated, late.extrapolated_s) == (True, 0.0)
    laser = buffer.lookup("map", "laser", S // 2)
    expected = MAP_ODOM @ pose((1.0, 0.0, 0.0), rot_z(math.pi / 4)) @ BASE_LASER
    assert np.allclose(lookup_matrix(laser), expected, atol=1e-6)


def test_lookup_outside_the_recording_clamps_and_reports_extrapolation() -> None:
    buffer = TfBuffer(samples())
    after = buffer.lookup("odom", "base_link", 3 * S + S // 2)
    assert after.translation == pytest.approx((2.0, 2.0, 0.0), abs=1e-6)
    assert after.extrapolated_s == pytest.approx(1.5)
    before = buffer.lookup("map", "laser", -2 * S)
    assert before.extrapolated_s == pytest.approx(2.0)
    assert before.interpolated is False


def test_sibling_frames_chain_through_their_common_parent() -> None:
    lookup = TfBuffer(samples()).lookup("laser", "imu", S)
    assert lookup.chain == ["imu", "base_link", "laser"]
    expected = np.linalg.inv(BASE_LASER) @ pose((0.0, 0.1, 0.0), np.eye(3))
    assert np.allclose(lookup_matrix(lookup), expected, atol=1e-6)


def test_same_frame_lookup_is_identity() -> None:
    lookup = TfBuffer(samples()).lookup("odom", "/odom", 5 * S)
    assert lookup.translation == (0.0, 0.0, 0.0)
    assert lookup.rotation == (0.0, 0.0, 0.0, 1.0)
    assert (lookup.chain, lookup.extrapolated_s) == (["odom"], 0.0)


def test_tree_lists_frames_roots_order_and_edge_rates() -> None:
    tree = TfBuffer(samples()).tree(S // 2 - 1)
    assert tree.frames == ["base_link", "imu", "laser", "map", "odom"]
    assert tree.roots == ["map"]
    assert tree.order == ["map", "odom", "base_link", "imu", "laser"]
    assert [(e.parent, e.child) for e in tree.edges] == [
        ("map", "odom"),
        ("odom", "base_link"),
        ("base_link", "imu"),
        ("base_link", "laser"),
    ]
    odom_base = tree.edges[1]
    assert (odom_base.static, odom_base.count, odom_base.first_ns, odom_base.last_ns) == (False, 3, 0, 2 * S)
    assert odom_base.rate_hz == pytest.approx(1.0)
    assert odom_base.nearest_ns == 0
    assert tree.edges[0].static
    assert tree.edges[0].rate_hz is None
    assert tree.multiple_parents == {}
    assert TfBuffer(samples()).tree().edges[1].nearest_ns is None


def test_frame_with_two_parents_is_flagged_and_latest_parent_wins() -> None:
    extra = TfSample(3 * S // 2, "map", "base_link", (10.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0), static=False)
    buffer = TfBuffer([*samples(), extra])
    assert buffer.tree().multiple_parents == {"base_link": ["map", "odom"]}
    recent = buffer.lookup("map", "base_link", 18 * S // 10)
    assert recent.chain == ["base_link", "map"]
    assert recent.translation == pytest.approx((10.0, 0.0, 0.0))
    before = buffer.lookup("map", "base_link", 12 * S // 10)
    assert before.chain == ["base_link", "odom", "map"]


def test_leading_slashes_are_normalised() -> None:
    assert normalize_frame("/base_link") == "base_link"
    buffer = TfBuffer(samples())
    assert "map" in buffer.frames
    assert "/map" not in buffer.frames
    assert buffer.lookup("/map", "/odom", 0).translation == pytest.approx((1.0, 2.0, 0.0))


def test_disconnected_trees_raise_naming_both_roots() -> None:
    gps = TfSample(0, "world", "gps", (0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0), static=True)
    buffer = TfBuffer([*samples(), gps])
    assert buffer.tree().roots == ["map", "world"]
    with pytest.raises(ValueError, match="not connected") as error:
        buffer.lookup("laser", "gps", 0)
    assert "'map'" in str(error.value)
    assert "'world'" in str(error.value)


def test_unknown_frame_suggests_close_names() -> None:
    with pytest.raises(ValueError, match="Did you mean 'laser'"):
        TfBuffer(samples()).lookup("map", "lazer", 0)


def test_unusable_samples_are_ignored_and_counted() -> None:
    bad = [
        TfSample(0, "a", "a", (0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0), static=True),
        TfSample(0, "a", "b", (math.nan, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0), static=True),
        TfSample(0, "a", "c", (0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 0.0), static=True),
    ]
    tree = TfBuffer([*samples(), *bad]).tree()
    assert tree.ignored_samples == 3
    assert "a" not in tree.frames
