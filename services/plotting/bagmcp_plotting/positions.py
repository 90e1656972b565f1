"""Where a robot was, as a plot needs it: x and y of a pose topic in metres (GPS fixes as metres east and
north of the first valid fix, the conversion trajectories use), and when it first moved."""

from __future__ import annotations

import math

import numpy as np

from bagmcp_plotting.data import PathSeries, read_fields
from bagmcp_shared.access import OpenBag
from bagmcp_shared.errors import ArgumentError
from bagmcp_shared.gps_metres import read_local_fixes
from bagmcp_shared.jobs import Progress
from bagmcp_shared.laser_ranges import MOVING_MPS
from bagmcp_shared.topics import POSE_SOURCES, choose_pose_topic, is_fix


def positions(
    ob: OpenBag, topic: str, msgtype: str, lo: int, hi: int, progress: Progress
) -> tuple[PathSeries, PathSeries]:
    """x and y of the pose topic ``topic`` (of ``msgtype``) in [lo, hi], in metres."""
    if not is_fix(msgtype):
        source = POSE_SOURCES[msgtype]
        x, y = read_fields(ob, topic, [source.axis(axis) for axis in "xy"], lo, hi, progress)
        return x, y
    fixes = read_local_fixes(ob, topic, lo, hi, progress)
    return (
        PathSeries(f"{topic} east", topic, "east", "m", fixes.log_ns, fixes.metres.east_m),
        PathSeries(f"{topic} north", topic, "north", "m", fixes.log_ns, fixes.metres.north_m),
    )


def motion_start(ob: OpenBag, progress: Progress) -> int | None:
    """Log time of the first pose of the bag's pose topic that moved (speed over MOVING_MPS), or None."""
    try:
        topic, msgtype, _ = choose_pose_topic(ob, None)
        x, y = positions(ob, topic, msgtype, ob.start_ns, ob.end_ns, progress)
    except ArgumentError:
        return None
    dt = np.diff(x.t_ns).astype(np.float64) / 1e9
    speed = np.hypot(np.diff(x.values), np.diff(y.values)) / np.where(dt > 0, dt, math.inf)
    moving = np.flatnonzero(speed > MOVING_MPS)
    return int(x.t_ns[moving[0]]) if moving.size else None
