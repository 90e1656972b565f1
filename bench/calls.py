"""What the benchmark asks of every bag: each tool once cold, then warm, with its target and its floor."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

Arguments = Callable[[str, float, int], dict[str, Any]]  # (bag name, bag duration s, repetition) -> arguments
ODOM_PATHS = ["/odom.pose.pose.position.x", "/odom.twist.twist.linear.x"]
NEAR = {"x": 3.0, "y": 3.0, "radius": 0.2}  # the east point of the drive's circle
ANALYSIS = ("analyze_", "get_image_at_time", "get_tf_tree", "topic_statistics", "summarize_window")


def service_of(tool: str) -> str:
    """The stack service that answers ``tool``."""
    if tool.startswith("plot_"):
        return "plotting"
    return "analysis" if tool.startswith(ANALYSIS) else "bag-store"


@dataclass(frozen=True)
class Target:
    """``warm_ms``: the warm median must stay under it. ``cold_floor_factor``: the cold call must stay under
    this multiple of the floor (plus ``cold_plus_warm``: the tool's own warm median, e.g. rendering)."""

    warm_ms: float | None = None
    cold_floor_factor: float | None = None
    cold_plus_warm: bool = False
    issue: int = 11


@dataclass(frozen=True)
class BenchCall:
    label: str
    tool: str
    arguments: Arguments
    floor: str | None = None  # a key of bench.floors.FLOORS
    target: Target | None = None
    cheap: bool = False  # run in the concurrency and load tests

    def __reduce__(self) -> tuple[object, tuple[str]]:
        """Saved by label (its arguments are lambdas): a saved run is re-rendered with the calls as defined."""
        return call_labelled, (self.label,)


def _mid(duration_s: float, rep: int) -> float:
    """A time in the middle half of the bag, different on every repetition."""
    return round(duration_s / 4 + (duration_s / 2) * ((rep * 0.618) % 1.0), 3)


CALLS: tuple[BenchCall, ...] = (
    BenchCall("list_bags", "list_bags", lambda b, d, r: {}, target=Target(warm_ms=20), cheap=True),
    BenchCall("bag_info", "bag_info", lambda b, d, r: {"bag": b}, target=Target(warm_ms=20), cheap=True),
    BenchCall(
        "get_message_at_time /odom",
        "get_message_at_time",
        lambda b, d, r: {"bag": b, "topic": "/odom", "time": _mid(d, r)},
        floor="open_1s",
        target=Target(warm_ms=10, cold_floor_factor=1.0),
        cheap=True,
    ),
    BenchCall(
        "get_messages_in_range 1 s /odom",
        "get_messages_in_range",
        lambda b, d, r: {
            "bag": b,
            "topic": "/odom",
            "start": _mid(d, r),
            "end": _mid(d, r) + 1.0,
            "fields": ["pose.pose.position.x", "pose.pose.position.y", "twist.twist.linear.x"],
            "max_messages": 200,
        },
        floor="open_1s",
        target=Target(warm_ms=20),
    ),
    BenchCall("describe_topic /odom", "describe_topic", lambda b, d, r: {"bag": b, "topic": "/odom"}),
    BenchCall(
        "search_messages near_position (index)",
        "search_messages",
        lambda b, d, r: {"bag": b, "topic": "/odom", "condition": "near_position", "value": NEAR},
        floor="odom",
        target=Target(warm_ms=30),
    ),
    BenchCall(
        "analyze_trajectory",
        "analyze_trajectory",
        lambda b, d, r: {"bag": b, "topic": "/odom"},
        floor="odom",
        target=Target(warm_ms=200, cold_floor_factor=1.5, issue=9),
    ),
    BenchCall(
        "analyze_lidar_scan within, whole bag",
        "analyze_lidar_scan",
        lambda b, d, r: {"bag": b, "topic": "/scan", "within": 0.6},
        floor="scan",
        target=Target(warm_ms=300, issue=9),
    ),
    BenchCall(
        "get_image_at_time",
        "get_image_at_time",
        lambda b, d, r: {"bag": b, "topic": "/camera/image_raw", "time": _mid(d, r)},
        floor="image",
        target=Target(warm_ms=150, issue=9),
    ),
    BenchCall("analyze_logs", "analyze_logs", lambda b, d, r: {"bag": b}, floor="logs"),
    BenchCall("get_tf_tree", "get_tf_tree", lambda b, d, r: {"bag": b}, floor="tf"),
    BenchCall("topic_statistics /odom", "topic_statistics", lambda b, d, r: {"bag": b, "topic": "/odom"}, floor="odom"),
    BenchCall(
        "summarize_window 10 s",
        "summarize_window",
        lambda b, d, r: {"bag": b, "start": _mid(d, r), "end": _mid(d, r) + min(10.0, d / 4)},
    ),
    BenchCall(
        "plot_timeseries 2 odometry paths",
        "plot_timeseries",
        lambda b, d, r: {"bag": b, "paths": ODOM_PATHS, "end": round(d - 0.01 * (r + 1), 3)},
        floor="odom",
        target=Target(warm_ms=500, cold_floor_factor=1.5, cold_plus_warm=True, issue=10),
    ),
    BenchCall(
        "plot_2d trajectory",
        "plot_2d",
        lambda b, d, r: {"bag": b, "topic": "/odom", "end": round(d - 0.01 * (r + 1), 3)},
        floor="odom",
        target=Target(warm_ms=500, cold_floor_factor=1.5, cold_plus_warm=True, issue=10),
    ),
    BenchCall(
        "filter_bag /odom + /cmd_vel, 5 s",
        "filter_bag",
        lambda b, d, r: {
            "bag": b,
            "name": f"{b}-cut-{r}",
            "include_topics": ["/odom", "/cmd_vel"],
            "start": _mid(d, r),
            "end": _mid(d, r) + min(5.0, d / 4),
        },
    ),
)


def call_labelled(label: str) -> BenchCall:
    return next(c for c in CALLS if c.label == label)
