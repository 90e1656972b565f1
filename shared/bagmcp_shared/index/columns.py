"""What the columnar index extracts: the numeric columns of common message types, and how to read one
column (a message path, or a derived value such as a scan's closest range) from a decoded message."""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable

from bagmcp_shared.bags import BagReader
from bagmcp_shared.laser_ranges import laser_ranges
from bagmcp_shared.paths import check_steps, extract, parse_field_path

Getter = Callable[[object], float | int | str]

_XYZ = ("x", "y", "z")
_ANGLES = ("roll", "pitch", "yaw")


def _vec(prefix: str, names: Iterable[str] = _XYZ) -> tuple[str, ...]:
    return tuple(f"{prefix}.{n}" for n in names)


_POSE = (*_vec("position"), *_vec("orientation", _ANGLES))
_TWIST = (*_vec("linear"), *_vec("angular"))
_NUMBERS = (
    "Float32",
    "Float64",
    "Int8",
    "Int16",
    "Int32",
    "Int64",
    "UInt8",
    "UInt16",
    "UInt32",
    "UInt64",
    "Bool",
)
INDEXED_COLUMNS: dict[str, tuple[str, ...]] = {
    "nav_msgs/msg/Odometry": (*(f"pose.pose.{c}" for c in _POSE), *(f"twist.twist.{c}" for c in _TWIST)),
    "geometry_msgs/msg/Pose": _POSE,
    "geometry_msgs/msg/PoseStamped": tuple(f"pose.{c}" for c in _POSE),
    "geometry_msgs/msg/PoseWithCovarianceStamped": tuple(f"pose.pose.{c}" for c in _POSE),
    "geometry_msgs/msg/Twist": _TWIST,
    "geometry_msgs/msg/TwistStamped": tuple(f"twist.{c}" for c in _TWIST),
    "sensor_msgs/msg/Imu": (
        *_vec("orientation", _ANGLES),
        *_vec("angular_velocity"),
        *_vec("linear_acceleration"),
    ),
    "sensor_msgs/msg/NavSatFix": ("latitude", "longitude", "altitude", "status.status"),
    "sensor_msgs/msg/BatteryState": ("voltage", "current", "percentage"),
    "sensor_msgs/msg/LaserScan": ("min_range", "min_bearing"),
    "rosgraph_msgs/msg/Log": ("level",),
    "rcl_interfaces/msg/Log": ("level",),
    **{f"std_msgs/msg/{n}": ("data",) for n in _NUMBERS},
}


def scan_minimum(message: object) -> tuple[float, float]:
    """Closest valid range of a LaserScan and its bearing (rad); NaN when no beam is valid."""
    return laser_ranges(message).closest() or (math.nan, math.nan)


DERIVED: dict[str, Getter] = {
    "min_range": lambda m: scan_minimum(m)[0],
    "min_bearing": lambda m: scan_minimum(m)[1],
}


def column_getter(reader: BagReader, msgtype: str, column: str) -> Getter:
    """A function reading ``column`` from a decoded message; wrong paths raise MessagePathError."""
    if column in DERIVED and msgtype == "sensor_msgs/msg/LaserScan":
        return DERIVED[column]
    steps = parse_field_path(column)
    check_steps(reader.decoder.typestore(msgtype), msgtype, steps)
    return lambda message: extract(message, steps)  # type: ignore[return-value]
