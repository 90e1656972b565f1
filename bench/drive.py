"""The benchmark drive in closed form, and its messages as rosbags objects.

The robot drives a circle of radius 3 m at 0.5 m/s and stops for 5 s every 40 s, inside a 12 m x 12 m room
with a post it passes close by. Topics: /odom and /tf at 100 Hz, /cmd_vel at 20 Hz, /scan (LaserScan, 720
beams) and 1 MB mono8 images at 10 Hz, /rosout at 1 Hz, /tf_static once. The images make up the bag's size.
"""

from __future__ import annotations

import math
from collections.abc import Iterator

import numpy as np
import numpy.typing as npt
from rosbags.typesys.store import Typestore

from tests.fixtures.bagfactory import make
from tests.fixtures.drive_motion_messages import TF_TYPE, Message, header, stamp, transform_stamped
from tests.fixtures.drive_tf import Transform, yaw_quaternion

ODOM_HZ, CMD_HZ, SCAN_HZ, IMAGE_HZ, LOG_HZ = 100, 20, 10, 10, 1
RADIUS_M, SPEED_MPS = 3.0, 0.5
PERIOD_S, DRIVING_S = 40.0, 35.0
BEAMS = 720
ROOM_M = (-6.0, 6.0, -3.0, 9.0)  # x min, x max, y min, y max
POST_XY_M, POST_RADIUS_M = (3.6, 3.0), 0.1  # 0.5 m outside the circle at its east point
IMAGE_SIDE = 1000  # 1000 x 1000 mono8: 1,000,000 bytes of pixels
LEVELS_ROS1, LEVELS_ROS2 = (2, 2, 2, 4, 8), (20, 20, 20, 30, 40)


def arc_m(t_s: float) -> float:
    """Distance driven by ``t_s``."""
    laps, rest = divmod(t_s, PERIOD_S)
    return SPEED_MPS * (laps * DRIVING_S + min(rest, DRIVING_S))


def moving(t_s: float) -> bool:
    return t_s % PERIOD_S < DRIVING_S


def pose_at(t_s: float) -> tuple[float, float, float]:
    """x m, y m, yaw rad (unwrapped) of base_link in odom."""
    angle = arc_m(t_s) / RADIUS_M
    return RADIUS_M * math.sin(angle), RADIUS_M * (1.0 - math.cos(angle)), angle


def scan_ranges(t_s: float) -> npt.NDArray[np.float32]:
    """Ranges from the robot to the room's walls and the post, beams from -pi counter-clockwise."""
    x, y, yaw = pose_at(t_s)
    angles = yaw - math.pi + np.arange(BEAMS) * (2 * math.pi / BEAMS)
    dx, dy = np.cos(angles), np.sin(angles)
    x0, x1, y0, y1 = ROOM_M
    with np.errstate(divide="ignore"):
        tx = np.where(dx > 0, (x1 - x) / dx, (x0 - x) / dx)
        ty = np.where(dy > 0, (y1 - y) / dy, (y0 - y) / dy)
    ranges = np.minimum(np.abs(tx), np.abs(ty))
    px, py = POST_XY_M[0] - x, POST_XY_M[1] - y
    along = px * dx + py * dy
    miss = np.hypot(px - along * dx, py - along * dy)
    hits = (along > 0) & (miss < POST_RADIUS_M)
    ranges = np.where(hits, np.minimum(ranges, along - np.sqrt(np.maximum(POST_RADIUS_M**2 - miss**2, 0))), ranges)
    result: npt.NDArray[np.float32] = ranges.astype(np.float32)
    return result


def _ticks(hz: int, duration_s: float) -> range:
    return range(int(duration_s * hz) + 1)


def _ns(tick: int, hz: int) -> int:
    return tick * (1_000_000_000 // hz)


def motion(store: Typestore, *, ros1: bool, duration_s: float) -> Iterator[Message]:
    """/odom and /tf at 100 Hz, /cmd_vel at 20 Hz."""
    for tick in _ticks(ODOM_HZ, duration_s):
        offset_ns = _ns(tick, ODOM_HZ)
        t_s = offset_ns / 1e9
        x, y, yaw = pose_at(t_s)
        linear, angular = (SPEED_MPS, SPEED_MPS / RADIUS_M) if moving(t_s) else (0.0, 0.0)
        edge = Transform("odom", "base_link", (x, y, 0.0), yaw_quaternion(yaw))
        pose = {"position": {"x": x, "y": y}, "orientation": dict(zip("xyzw", edge.rotation_xyzw, strict=True))}
        yield (
            "/odom",
            "nav_msgs/msg/Odometry",
            offset_ns,
            make(
                store,
                "nav_msgs/msg/Odometry",
                header=header(ros1=ros1, offset_ns=offset_ns, frame="odom"),
                child_frame_id="base_link",
                pose={"pose": pose},
                twist={"twist": {"linear": {"x": linear}, "angular": {"z": angular}}},
            ),
        )
        stamped = transform_stamped(store, ros1=ros1, offset_ns=offset_ns, transform=edge)
        yield "/tf", TF_TYPE, offset_ns, make(store, TF_TYPE, transforms=[stamped])
        if tick % (ODOM_HZ // CMD_HZ) == 0:
            twist = make(store, "geometry_msgs/msg/Twist", linear={"x": linear}, angular={"z": angular})
            yield "/cmd_vel", "geometry_msgs/msg/Twist", offset_ns, twist


def sensors(store: Typestore, *, ros1: bool, duration_s: float) -> Iterator[Message]:
    """/scan and /camera/image_raw at 10 Hz."""
    base = np.add.outer(np.arange(IMAGE_SIDE), np.arange(IMAGE_SIDE)).astype(np.uint8).ravel()
    for tick in _ticks(SCAN_HZ, duration_s):
        offset_ns = _ns(tick, SCAN_HZ)
        scan = make(
            store,
            "sensor_msgs/msg/LaserScan",
            header=header(ros1=ros1, offset_ns=offset_ns, frame="laser"),
            angle_min=np.float32(-math.pi),
            angle_max=np.float32(math.pi - 2 * math.pi / BEAMS),
            angle_increment=np.float32(2 * math.pi / BEAMS),
            scan_time=np.float32(1 / SCAN_HZ),
            range_min=np.float32(0.05),
            range_max=np.float32(30.0),
            ranges=scan_ranges(offset_ns / 1e9),
        )
        yield "/scan", "sensor_msgs/msg/LaserScan", offset_ns, scan
        image = make(
            store,
            "sensor_msgs/msg/Image",
            header=header(ros1=ros1, offset_ns=offset_ns, frame="camera"),
            height=np.uint32(IMAGE_SIDE),
            width=np.uint32(IMAGE_SIDE),
            encoding="mono8",
            step=np.uint32(IMAGE_SIDE),
            data=base + np.uint8(tick % 256),
        )
        yield "/camera/image_raw", "sensor_msgs/msg/Image", offset_ns, image


def records(store: Typestore, *, ros1: bool, duration_s: float) -> Iterator[Message]:
    """/tf_static once, /rosout at 1 Hz (INFO mostly, a WARN and an ERROR every 5 s)."""
    statics = [
        Transform("base_link", "laser", (0.2, 0.0, 0.15), (0.0, 0.0, 0.0, 1.0)),
        Transform("base_link", "camera", (0.1, 0.0, 0.3), (0.0, 0.0, 0.0, 1.0)),
    ]
    stamped = [transform_stamped(store, ros1=ros1, offset_ns=0, transform=t) for t in statics]
    yield "/tf_static", TF_TYPE, 0, make(store, TF_TYPE, transforms=stamped)
    levels = LEVELS_ROS1 if ros1 else LEVELS_ROS2
    for tick in _ticks(LOG_HZ, duration_s):
        offset_ns = _ns(tick, LOG_HZ)
        fields: dict[str, object] = {
            "level": np.uint8(levels[tick % len(levels)]),
            "name": "/planner",
            "msg": f"tick {tick}",
            "file": "planner.cpp",
            "function": "tick",
            "line": np.uint32(1),
        }
        if ros1:
            when = header(ros1=True, offset_ns=offset_ns, frame="")
            yield (
                "/rosout",
                "rosgraph_msgs/msg/Log",
                offset_ns,
                make(store, "rosgraph_msgs/msg/Log", header=when, **fields),
            )
        else:
            log = make(store, "rcl_interfaces/msg/Log", stamp=stamp(offset_ns), **fields)
            yield "/rosout", "rcl_interfaces/msg/Log", offset_ns, log
