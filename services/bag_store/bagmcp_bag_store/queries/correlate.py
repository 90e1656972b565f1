"""Correlation: the nearest message of another topic for each match, found by time index.

A partner is shown as what answers "where was the robot, how was it moving then" (``PARTNER_VIEW``), not
whole: an Odometry is 8.9 K characters for 20 matches with its 72 covariance zeros, its view 1.4 K. Asking
``correlate_topic="/odom.pose.pose"`` shows that path instead, ``"/odom."`` (a bare dot) the whole message.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from bagmcp_bag_store.reports import Correlated
from bagmcp_shared.access import OpenBag
from bagmcp_shared.errors import TopicNotFoundError
from bagmcp_shared.index import ColumnIndex
from bagmcp_shared.jsonify import fit
from bagmcp_shared.paths import Step, check_steps, extract, format_steps, parse_message_path

PARTNER_BUDGET_BYTES = 1500
PARTNER_VIEW = {
    "nav_msgs/msg/Odometry": (
        "pose.pose.position",
        "pose.pose.orientation.yaw",
        "twist.twist.linear",
        "twist.twist.angular.z",
    ),
    "geometry_msgs/msg/PoseStamped": ("pose.position", "pose.orientation.yaw"),
    "geometry_msgs/msg/PoseWithCovarianceStamped": ("pose.pose.position", "pose.pose.orientation.yaw"),
    "geometry_msgs/msg/TransformStamped": ("child_frame_id", "transform.translation", "transform.rotation.yaw"),
    "sensor_msgs/msg/NavSatFix": ("latitude", "longitude", "altitude", "status.status"),
    "sensor_msgs/msg/Imu": ("orientation.yaw", "angular_velocity", "linear_acceleration"),
    "sensor_msgs/msg/LaserScan": ("range_min", "range_max", "angle_min", "angle_max"),
}


def partner_view(ob: OpenBag, asked: str) -> tuple[str, list[tuple[Step, ...]] | None]:
    """The partner topic and the paths to show of it (None: the whole message), checked against its type."""
    try:
        return ob.topic_name(asked), _default_view(ob, ob.topic_name(asked))
    except TopicNotFoundError:
        if "." not in asked:
            raise
    path = parse_message_path(asked)
    topic = ob.topic_name(path.topic)
    if not path.steps:
        return topic, None
    msgtype = ob.msgtype(topic)
    check_steps(ob.reader.decoder.typestore(msgtype), msgtype, path.steps)
    return topic, [path.steps]


def _default_view(ob: OpenBag, topic: str) -> list[tuple[Step, ...]] | None:
    view = PARTNER_VIEW.get(ob.msgtype(topic))
    return None if view is None else [parse_message_path(f"{topic}.{p}").steps for p in view]


def _shown(message: object, view: list[tuple[Step, ...]] | None) -> object:
    return message if view is None else {format_steps(steps): extract(message, steps) for steps in view}


def _times(ob: OpenBag, index: ColumnIndex | None, topic: str, lo: int, hi: int) -> npt.NDArray[np.int64]:
    if index is not None and index.columns(topic):
        return index.read(topic, [], start_ns=lo, stop_ns=hi).t_ns
    stamps = [raw.log_time_ns for raw in ob.reader.messages([topic], start_ns=lo, stop_ns=hi)]
    return np.asarray(stamps, dtype=np.int64)


def _nearest(candidates: npt.NDArray[np.int64], t: int, tolerance_ns: int) -> int | None:
    position = int(np.searchsorted(candidates, t))
    near = [int(candidates[i]) for i in (position - 1, position) if 0 <= i < len(candidates)]
    best = min(near, key=lambda c: abs(c - t), default=None)
    return best if best is not None and abs(best - t) <= tolerance_ns else None


def correlate(
    ob: OpenBag, index: ColumnIndex | None, asked: str, times_ns: list[int], *, tolerance_ns: int
) -> list[Correlated | None]:
    """For each time, the nearest message of the ``asked`` topic (or /topic.path) within ``tolerance_ns``, or
    None.

    Candidate times come from the index (or one raw pass); the chosen partners are then decoded in
    a single pass over their span.
    """
    name, view = partner_view(ob, asked)
    if not times_ns:
        return []
    candidates = _times(ob, index, name, min(times_ns) - tolerance_ns, max(times_ns) + tolerance_ns + 1)
    chosen = [_nearest(candidates, t, tolerance_ns) for t in times_ns]
    wanted = {c for c in chosen if c is not None}
    decoded: dict[int, Correlated] = {}
    if wanted:
        for raw in ob.reader.messages([name], start_ns=min(wanted), stop_ns=max(wanted) + 1):
            if raw.log_time_ns in wanted and raw.log_time_ns not in decoded:
                data = fit(_shown(ob.reader.decode(raw), view), PARTNER_BUDGET_BYTES)
                decoded[raw.log_time_ns] = Correlated(
                    topic=name, time=ob.instant(raw.log_time_ns), delta_s=0.0, data=data
                )
    return [
        decoded[c].model_copy(update={"delta_s": (c - t) / 1e9}) if c is not None else None
        for c, t in zip(chosen, times_ns, strict=True)
    ]
