"""Units of common ROS message fields (REP 103), found from a field path's last parts."""

from __future__ import annotations

_BY_PARENT = {
    "linear": "m/s",
    "angular": "rad/s",
    "linear_acceleration": "m/s^2",
    "angular_velocity": "rad/s",
    "position": "m",
    "translation": "m",
    "magnetic_field": "T",
}
_BY_FIELD = {
    "ranges": "m",
    "range_min": "m",
    "range_max": "m",
    "range": "m",
    "angle_min": "rad",
    "angle_max": "rad",
    "angle_increment": "rad",
    "time_increment": "s",
    "scan_time": "s",
    "roll": "rad",
    "pitch": "rad",
    "yaw": "rad",
    "latitude": "deg",
    "longitude": "deg",
    "altitude": "m",
    "temperature": "degC",
    "voltage": "V",
    "current": "A",
    "percentage": "fraction (0..1)",
    "nanosec": "ns",
    "sec": "s",
}
_WRENCH_PARENT = {"force": "N", "torque": "N*m"}


def unit_of(path: str) -> str | None:
    """The unit of a field path such as ``twist.twist.linear.x``; None when unknown."""
    parts = [p.split("[")[0] for p in path.split(".")]
    leaf = parts[-1]
    parent = parts[-2] if len(parts) > 1 else ""
    if leaf in ("x", "y", "z"):
        if parent == "linear" and "accel" in parts:
            return "m/s^2"
        return _BY_PARENT.get(parent) or _WRENCH_PARENT.get(parent)
    return _BY_FIELD.get(leaf)
