"""Which topic a question means when the caller does not say: the pose topic of a trajectory, the lidar
of an obstacle question. The answer always says which one was chosen (and the alternatives)."""

from __future__ import annotations

from dataclasses import dataclass

from bagmcp_shared.access import OpenBag
from bagmcp_shared.errors import ArgumentError
from bagmcp_shared.flight_types import (
    FLIGHT_FIXES,
    FLIGHT_POSE_ORDER,
    FLIGHT_POSES,
    FixSource,
    fix_source,
    heading_field,
)

SCAN = "sensor_msgs/msg/LaserScan"
CLOUD = "sensor_msgs/msg/PointCloud2"
GPS = "sensor_msgs/msg/NavSatFix"


@dataclass(frozen=True)
class PoseSource:
    """Where a pose type keeps its position and orientation (message paths): ``position`` holds x, y, z
    (top-level fields when ""); the yaw comes from the ``orientation`` quaternion or the ``yaw`` field."""

    position: str
    orientation: str | None
    yaw: str | None = None

    def axis(self, name: str) -> str:
        return f"{self.position}.{name}" if self.position else name

    @property
    def yaw_column(self) -> str | None:
        return self.yaw or (f"{self.orientation}.yaw" if self.orientation else None)


POSE_SOURCES: dict[str, PoseSource] = {  # in order of preference; GPS-like types have no pose fields
    "nav_msgs/msg/Odometry": PoseSource("pose.pose.position", "pose.pose.orientation"),
    "geometry_msgs/msg/PoseWithCovarianceStamped": PoseSource("pose.pose.position", "pose.pose.orientation"),
    "geometry_msgs/msg/PoseStamped": PoseSource("pose.position", "pose.orientation"),
    "geometry_msgs/msg/TransformStamped": PoseSource("transform.translation", "transform.rotation"),
    GPS: PoseSource("", None),
    **dict.fromkeys(FLIGHT_POSE_ORDER, PoseSource("", None)),  # x, y, z top level; the heading: pose_source
}
_PREFERENCE = list(POSE_SOURCES)
NAVSATFIX = FixSource("latitude", "longitude", "altitude", "status.status", 0.0)


def pose_source(ob: OpenBag, msgtype: str) -> PoseSource:
    """Where ``msgtype`` keeps its pose; a flight local position's heading field depends on the log's version."""
    if msgtype in FLIGHT_POSES:
        return PoseSource("", None, heading_field(ob.reader.decoder.typestore(msgtype), msgtype))
    return POSE_SOURCES[msgtype]


def is_fix(msgtype: str) -> bool:
    """A GPS-like type: positions are latitude/longitude, turned into metres east/north of the first fix."""
    return msgtype == GPS or msgtype in FLIGHT_FIXES


def fix_columns(ob: OpenBag, msgtype: str) -> FixSource:
    """Where the fixes of ``msgtype`` are (ArgumentError when its definition has none of the known layouts)."""
    if msgtype == GPS:
        return NAVSATFIX
    found = fix_source(ob.reader.decoder.typestore(msgtype), msgtype)
    if found is None:
        raise ArgumentError(f"{msgtype} in {ob.name} has none of the known latitude/longitude field layouts")
    return found


def _rank(name: str, msgtype: str, count: int) -> tuple[int, int, int]:
    named = 0 if "odom" in name.lower() or "pose" in name.lower() else 1
    return (_PREFERENCE.index(msgtype), named, -count)


def pose_topics(ob: OpenBag) -> list[tuple[str, str]]:
    """Pose topics with at least two messages, best first: (topic, type)."""
    found = {(t.name, t.type, t.count) for t in ob.summary.topics if t.type in POSE_SOURCES and t.count >= 2}
    return [(name, msgtype) for name, msgtype, _ in sorted(found, key=lambda f: _rank(*f))]


def choose_pose_topic(ob: OpenBag, topic: str | None) -> tuple[str, str, list[str]]:
    """The topic asked for (its type must carry a pose), or the obvious one; and the other candidates."""
    candidates = pose_topics(ob)
    if topic is not None:
        name, msgtype = ob.topic_name(topic), ob.msgtype(topic)
        if msgtype not in POSE_SOURCES:
            kinds = ", ".join(t.rsplit("/", 1)[-1] for t in POSE_SOURCES)
            raise ArgumentError(f"{name} is {msgtype}, which carries no pose; give a topic of type {kinds}")
        return name, msgtype, [c for c, _ in candidates if c != name]
    if not candidates:
        raise ArgumentError(f"{ob.name} has no odometry, pose, transform or GPS topic with two or more messages")
    (name, msgtype), rest = candidates[0], candidates[1:]
    return name, msgtype, [c for c, _ in rest]


def choose_lidar_topic(ob: OpenBag, topic: str | None) -> tuple[str, str]:
    """The LaserScan or PointCloud2 topic asked for, or the obvious one (scans before clouds, /scan first)."""
    if topic is not None:
        name, msgtype = ob.topic_name(topic), ob.msgtype(topic)
        if msgtype not in (SCAN, CLOUD):
            raise ArgumentError(f"{name} is {msgtype}; give a LaserScan or PointCloud2 topic")
        return name, msgtype
    found = sorted(
        (t.type != SCAN, "scan" not in t.name, -t.count, t.name, t.type)
        for t in ob.summary.topics
        if t.type in (SCAN, CLOUD) and t.count
    )
    if not found:
        raise ArgumentError(f"{ob.name} has no LaserScan or PointCloud2 topic")
    return found[0][3], found[0][4]
