"""Quaternion and 3-D vector math on plain tuples (x, y, z, w), REP 103 conventions, ZYX roll/pitch/yaw."""

from __future__ import annotations

import math

Quat = tuple[float, float, float, float]
Vec3 = tuple[float, float, float]

IDENTITY: Quat = (0.0, 0.0, 0.0, 1.0)


def norm(q: Quat) -> float:
    """Euclidean length of a quaternion."""
    return math.sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3])


def normalize(q: Quat) -> Quat:
    """Unit quaternion pointing the same way as q; raises ValueError for a zero or non-finite quaternion."""
    length = norm(q)
    if not math.isfinite(length) or length < 1e-12:
        raise ValueError(f"Quaternion {q} has zero or non-finite length; give a valid rotation (x, y, z, w).")
    return (q[0] / length, q[1] / length, q[2] / length, q[3] / length)


def canonical(q: Quat) -> Quat:
    """Normalised quaternion with w >= 0 (q and -q are the same rotation)."""
    x, y, z, w = normalize(q)
    if w < 0.0:
        return (-x, -y, -z, -w)
    return (x, y, z, w)


def multiply(a: Quat, b: Quat) -> Quat:
    """Hamilton product a * b: the rotation b followed by a (applied to vectors as a(b(v)))."""
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return (
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by - ax * bz + ay * bw + az * bx,
        aw * bz + ax * by - ay * bx + az * bw,
        aw * bw - ax * bx - ay * by - az * bz,
    )


def conjugate(q: Quat) -> Quat:
    """Conjugate (x, y, z negated); equals the inverse for unit quaternions."""
    return (-q[0], -q[1], -q[2], q[3])


def inverse(q: Quat) -> Quat:
    """Multiplicative inverse of any non-zero quaternion."""
    n2 = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]
    if not math.isfinite(n2) or n2 < 1e-24:
        raise ValueError(f"Quaternion {q} has zero or non-finite length and cannot be inverted.")
    x, y, z, w = conjugate(q)
    return (x / n2, y / n2, z / n2, w / n2)


def rotate(q: Quat, v: Vec3) -> Vec3:
    """Rotate vector v by the unit quaternion q (q v q*)."""
    x, y, z, _ = multiply(multiply(q, (v[0], v[1], v[2], 0.0)), conjugate(q))
    return (x, y, z)


def slerp(a: Quat, b: Quat, fraction: float) -> Quat:
    """Spherical linear interpolation from a (fraction 0) to b (fraction 1) along the shortest path."""
    qa = normalize(a)
    qb = normalize(b)
    dot = sum(qa[i] * qb[i] for i in range(4))
    if dot < 0.0:
        qb = (-qb[0], -qb[1], -qb[2], -qb[3])
        dot = -dot
    if dot > 0.9995:
        mixed = tuple(qa[i] + fraction * (qb[i] - qa[i]) for i in range(4))
        return normalize((mixed[0], mixed[1], mixed[2], mixed[3]))
    theta = math.acos(min(1.0, dot))
    sin_theta = math.sin(theta)
    wa = math.sin((1.0 - fraction) * theta) / sin_theta
    wb = math.sin(fraction * theta) / sin_theta
    return normalize(
        (wa * qa[0] + wb * qb[0], wa * qa[1] + wb * qb[1], wa * qa[2] + wb * qb[2], wa * qa[3] + wb * qb[3])
    )


def to_rpy(q: Quat) -> Vec3:
    """Roll, pitch, yaw in radians (ZYX / yaw-pitch-roll convention) of a rotation quaternion."""
    x, y, z, w = normalize(q)
    roll = math.atan2(2.0 * (w * x + y * z), 1.0 - 2.0 * (x * x + y * y))
    sin_pitch = max(-1.0, min(1.0, 2.0 * (w * y - z * x)))
    pitch = math.asin(sin_pitch)
    yaw = math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))
    return (roll, pitch, yaw)


def from_rpy(roll: float, pitch: float, yaw: float) -> Quat:
    """Quaternion of the rotation yaw about z, then pitch about y, then roll about x (ZYX, radians)."""
    cr, sr = math.cos(roll / 2.0), math.sin(roll / 2.0)
    cp, sp = math.cos(pitch / 2.0), math.sin(pitch / 2.0)
    cy, sy = math.cos(yaw / 2.0), math.sin(yaw / 2.0)
    return (
        sr * cp * cy - cr * sp * sy,
        cr * sp * cy + sr * cp * sy,
        cr * cp * sy - sr * sp * cy,
        cr * cp * cy + sr * sp * sy,
    )
