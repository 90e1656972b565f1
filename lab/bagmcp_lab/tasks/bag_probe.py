"""What a task needs to know about the bag before it is phrased: duration and which topic carries what, from
``bag_info``, so times and points are chosen from the bag itself (any bag, not only the generated drive)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from bagmcp_lab.toolbox import ToolBox

ODOMETRY = ("nav_msgs/msg/Odometry", "nav_msgs/Odometry")
TWIST = (
    "geometry_msgs/msg/Twist",
    "geometry_msgs/Twist",
    "geometry_msgs/msg/TwistStamped",
    "geometry_msgs/TwistStamped",
)
LASER = ("sensor_msgs/msg/LaserScan", "sensor_msgs/LaserScan")
IMAGE = (
    "sensor_msgs/msg/Image",
    "sensor_msgs/Image",
    "sensor_msgs/msg/CompressedImage",
    "sensor_msgs/CompressedImage",
)
LOGS = ("rcl_interfaces/msg/Log", "rosgraph_msgs/Log", "rosgraph_msgs/msg/Log")
TF = ("tf2_msgs/msg/TFMessage", "tf2_msgs/TFMessage", "tf/tfMessage")


@dataclass(frozen=True)
class BagProbe:
    bag: str
    duration_s: float
    topics: dict[str, str]  # name -> type
    counts: dict[str, int]
    first_s: dict[str, float]  # each topic's first message, seconds from the start

    def topic(self, types: tuple[str, ...], *, prefer: str = "") -> str | None:
        """The topic of one of ``types`` (one whose name contains ``prefer`` first, then the busiest)."""
        found = [name for name, kind in self.topics.items() if kind in types]
        found.sort(key=lambda name: (prefer not in name, -self.counts.get(name, 0), name))
        return found[0] if found else None

    def at(self, fraction: float) -> float:
        """A whole second at ``fraction`` of the bag's duration."""
        return float(round(self.duration_s * fraction))


async def probe_bag(box: ToolBox, bag: str) -> BagProbe:
    info = await box.reference("bag_info", bag=bag)
    topics: list[dict[str, Any]] = info["topics"]
    return BagProbe(
        bag=str(info.get("name", bag)),
        duration_s=float(info["duration_s"]),
        topics={str(t["name"]): str(t["type"]) for t in topics},
        counts={str(t["name"]): int(t.get("count", 0)) for t in topics},
        first_s={str(t["name"]): float((t.get("first") or {}).get("offset_s", 0.0)) for t in topics},
    )
