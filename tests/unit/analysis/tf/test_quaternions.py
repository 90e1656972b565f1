"""Tests for the quaternion helpers against closed-form rotations."""

from __future__ import annotations

import math

import pytest

from bagmcp_analysis.tf.quaternions import (
    canonical,
    conjugate,
    from_rpy,
    inverse,
    multiply,
    normalize,
    rotate,
    slerp,
    to_rpy,
)


def test_yaw_quarter_turn_maps_forward_to_left() -> None:
    q = from_rpy(0.0, 0.0, math.pi / 2)
    assert q == pytest.approx((0.0, 0.0, math.sqrt(0.5), math.sqrt(0.5)))
    assert rotate(q, (1.0, 0.0, 0.0)) == pytest.approx((0.0, 1.0, 0.0), abs=1e-12)


def test_roll_pitch_yaw_round_trip() -> None:
    for rpy in [(0.3, -0.4, 2.5), (-2.0, 1.2, -3.0), (0.0, 0.0, math.pi - 1e-3)]:
        assert to_rpy(from_rpy(*rpy)) == pytest.approx(rpy, abs=1e-12)


def test_zyx_order_applies_roll_first_then_yaw() -> None:
    q = from_rpy(math.pi / 2, 0.0, math.pi / 2)
    # roll 90° sends +y to +z, which yaw leaves alone; roll leaves +x alone and yaw 90° sends it to +y
    assert rotate(q, (0.0, 1.0, 0.0)) == pytest.approx((0.0, 0.0, 1.0), abs=1e-12)
    assert rotate(q, (1.0, 0.0, 0.0)) == pytest.approx((0.0, 1.0, 0.0), abs=1e-12)


def test_product_with_inverse_is_identity_and_composes_rotations() -> None:
    q = normalize((0.1, -0.7, 0.3, 0.6))
    assert multiply(q, conjugate(q)) == pytest.approx((0.0, 0.0, 0.0, 1.0), abs=1e-12)
    assert multiply(inverse((0.0, 0.0, 0.0, 2.0)), (0.0, 0.0, 0.0, 2.0)) == pytest.approx((0.0, 0.0, 0.0, 1.0))
    half = from_rpy(0.0, 0.0, 0.4)
    assert to_rpy(multiply(half, half))[2] == pytest.approx(0.8)


def test_slerp_takes_the_shortest_path_and_halves_the_angle() -> None:
    a = from_rpy(0.0, 0.0, 0.0)
    b = from_rpy(0.0, 0.0, 1.0)
    assert to_rpy(slerp(a, b, 0.5))[2] == pytest.approx(0.5)
    negated = (-b[0], -b[1], -b[2], -b[3])
    assert to_rpy(slerp(a, negated, 0.25))[2] == pytest.approx(0.25)
    c = from_rpy(0.0, 0.0, 3.0)
    d = from_rpy(0.0, 0.0, -3.0)  # 0.283 rad apart across ±pi
    assert abs(to_rpy(slerp(c, d, 0.5))[2]) == pytest.approx(math.pi)


def test_canonical_form_has_non_negative_w_and_zero_quaternion_is_rejected() -> None:
    assert canonical((0.0, 0.0, -2.0, -2.0)) == pytest.approx((0.0, 0.0, math.sqrt(0.5), math.sqrt(0.5)))
    with pytest.raises(ValueError, match="zero"):
        normalize((0.0, 0.0, 0.0, 0.0))
