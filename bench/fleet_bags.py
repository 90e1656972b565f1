"""The fleet benchmark's bags: many short drives (10 s, a third in each format) with known answers.

Bag ``i`` drives along +x from (0, y_i) at a constant speed v_i (0.2 .. 2.0 m/s), its lidar sees a wall that
ends at d_i metres, and every fifth bag logs an ERROR. So "max speed per bag" is v_i, "bags with an ERROR
log" are the fifth ones, and "bags that came within 0.5 m of (3, 0)" are those with |y_i| <= 0.5 that reach
x = 3 m (v_i >= 0.3): the benchmark checks its answers against these before timing them.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from rosbags.rosbag1 import Writer as Ros1Writer
from rosbags.rosbag2 import StoragePlugin
from rosbags.rosbag2 import Writer as Ros2Writer
from rosbags.typesys.store import Typestore

from tests.fixtures.bagfactory import BAG_KINDS, BagKind, make
from tests.fixtures.drive_bags import drive_typestore

DURATION_S = 10.0
ODOM_HZ, SCAN_HZ = 20, 10
BEAMS = 90
POINT = (3.0, 0.0)
NEAR_M = 0.5
Message = tuple[str, str, int, object]


@dataclass(frozen=True)
class ShortDrive:
    index: int
    kind: BagKind
    speed_mps: float
    y_m: float
    wall_m: float
    error: bool

    @property
    def start_ns(self) -> int:
        return 1_700_000_000_000_000_000 + self.index * 3_600_000_000_000  # one an hour

    @property
    def name(self) -> str:
        return f"fleet-{self.index:04d}"

    def passes_near(self) -> bool:
        return abs(self.y_m) <= NEAR_M and self.speed_mps * DURATION_S >= POINT[0]


def drive_of(index: int) -> ShortDrive:
    return ShortDrive(
        index=index,
        kind=BAG_KINDS[index % 3],
        speed_mps=round(0.2 + (index * 37 % 19) * 0.1, 3),
        y_m=round((index * 13 % 11) * 0.2 - 1.0, 3),
        wall_m=round(0.3 + (index * 7 % 10) * 0.2, 3),
        error=index % 5 == 0,
    )


def _header(drive: ShortDrive, offset_ns: int, frame: str, *, ros1: bool) -> dict[str, object]:
    sec, nanosec = divmod(drive.start_ns + offset_ns, 1_000_000_000)
    fields: dict[str, object] = {"stamp": {"sec": sec, "nanosec": nanosec}, "frame_id": frame}
    return {**fields, "seq": 0} if ros1 else fields


def _messages(store: Typestore, drive: ShortDrive, *, ros1: bool) -> Iterator[Message]:
    log_type = "rosgraph_msgs/msg/Log" if ros1 else "rcl_interfaces/msg/Log"
    level = (8 if ros1 else 40) if drive.error else (2 if ros1 else 20)
    for tick in range(int(DURATION_S * ODOM_HZ) + 1):
        offset_ns = tick * 1_000_000_000 // ODOM_HZ
        x = drive.speed_mps * offset_ns / 1e9
        pose = {"position": {"x": x, "y": drive.y_m}, "orientation": {"w": 1.0}}
        odom = make(
            store,
            "nav_msgs/msg/Odometry",
            header=_header(drive, offset_ns, "odom", ros1=ros1),
            child_frame_id="base_link",
            pose={"pose": pose},
            twist={"twist": {"linear": {"x": drive.speed_mps}}},
        )
        yield "/odom", "nav_msgs/msg/Odometry", offset_ns, odom
        if tick % (ODOM_HZ // SCAN_HZ) == 0:
            yield "/scan", "sensor_msgs/msg/LaserScan", offset_ns, _scan(store, drive, offset_ns, ros1=ros1)
    text = "planner failed to find a path" if drive.error else "planner ready"
    fields = {"level": level, "name": "/planner", "msg": text, "file": "planner.cpp", "function": "plan", "line": 7}
    stamp = _header(drive, 5_000_000_000, "", ros1=ros1)
    log = (
        make(store, log_type, header=stamp, **fields) if ros1 else make(store, log_type, stamp=stamp["stamp"], **fields)
    )
    yield "/rosout", log_type, 5_000_000_000, log


def _scan(store: Typestore, drive: ShortDrive, offset_ns: int, *, ros1: bool) -> object:
    """A wall ahead that comes from 5 m to ``wall_m`` over the drive."""
    closest = 5.0 - (5.0 - drive.wall_m) * offset_ns / (DURATION_S * 1e9)
    angles = np.linspace(-math.pi / 2, math.pi / 2, BEAMS)
    ranges = np.minimum(closest / np.maximum(np.cos(angles), 1e-3), 30.0).astype(np.float32)
    return make(
        store,
        "sensor_msgs/msg/LaserScan",
        header=_header(drive, offset_ns, "laser", ros1=ros1),
        angle_min=np.float32(-math.pi / 2),
        angle_max=np.float32(math.pi / 2),
        angle_increment=np.float32(math.pi / (BEAMS - 1)),
        range_min=np.float32(0.05),
        range_max=np.float32(30.0),
        ranges=ranges,
    )


@functools.cache
def _typestore(ros1: bool) -> Typestore:
    """One typestore per ROS version for every bag (each new one compiles its serializers again: 0.4 s)."""
    return drive_typestore(ros1=ros1)


def _write(drive: ShortDrive, path: Path) -> None:
    ros1 = drive.kind == "ros1"
    store = _typestore(ros1)
    serialize = store.serialize_ros1 if ros1 else store.serialize_cdr
    ordered = sorted(_messages(store, drive, ros1=ros1), key=lambda m: m[2])
    topics = dict.fromkeys((topic, msgtype) for topic, msgtype, _, _ in ordered)
    if ros1:
        with Ros1Writer(path) as writer1:
            opened1 = {t: writer1.add_connection(t, m, typestore=store) for t, m in topics}
            for topic, msgtype, offset_ns, message in ordered:
                writer1.write(opened1[topic], drive.start_ns + offset_ns, serialize(message, msgtype))
        return
    plugin = StoragePlugin.SQLITE3 if drive.kind == "ros2-sqlite3" else StoragePlugin.MCAP
    with Ros2Writer(path, version=9, storage_plugin=plugin) as writer2:
        opened2 = {t: writer2.add_connection(t, m, typestore=store) for t, m in topics}
        for topic, msgtype, offset_ns, message in ordered:
            writer2.write(opened2[topic], drive.start_ns + offset_ns, serialize(message, msgtype))


def fleet_bags(directory: Path, count: int) -> tuple[Path, list[ShortDrive]]:
    """``count`` short drives under ``directory/fleet-<count>/``, written only when missing."""
    folder = directory / f"fleet-{count}"
    folder.mkdir(parents=True, exist_ok=True)
    drives = [drive_of(i) for i in range(count)]
    for drive in drives:
        path = folder / (f"{drive.name}.bag" if drive.kind == "ros1" else drive.name)
        if not path.exists():
            _write(drive, path)
    return folder, drives
