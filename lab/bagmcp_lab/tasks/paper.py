"""The paper's ten tasks, phrased as its table phrases them, with times and points chosen from the bag and the
reference facts taken from the tools' own answers.

Each builder returns a Task, or a sentence saying why the bag cannot pose it (no lidar, no odometry)."""

from __future__ import annotations

import math
from collections.abc import Awaitable, Callable
from typing import Any

from bagmcp_lab.tasks.bag_probe import LASER, ODOMETRY, TF, TWIST, BagProbe
from bagmcp_lab.tasks.model import Fact, Requirement, Task, number_fact, verdict_fact, word_fact
from bagmcp_lab.toolbox import ToolBox

Builder = Callable[[ToolBox, BagProbe], Awaitable[Task | str]]
TIME_TOLERANCE_S = 0.15
POSITION_TOLERANCE_M = 0.05
NEAR_RADIUS_M = 0.5


def position_of(odometry: dict[str, Any]) -> dict[str, float]:
    """The position in an odometry message as search_messages shows a correlated one: by flat path
    (``pose.pose.position``) or nested."""
    flat = odometry.get("pose.pose.position")
    return dict(flat) if isinstance(flat, dict) else dict(odometry["pose"]["pose"]["position"])


def _on(probe: BagProbe, question: str) -> str:
    return f"{question} (bag: {probe.bag})"


def _one_tool(
    task_id: str, title: str, probe: BagProbe, question: str, tool: str, facts: tuple[Fact, ...] = ()
) -> Task:
    """A task on the probed bag that one tool answers."""
    return Task(task_id, title, _on(probe, question), (Requirement((tool,)),), facts)


async def list_bags(box: ToolBox, probe: BagProbe) -> Task | str:
    listing = await box.reference("list_bags", limit=500)
    names = [str(b["name"]) for b in listing["bags"]]
    facts = tuple(word_fact(f"bag {name}", name) for name in names[:20])
    return Task("p01-list-bags", "What bags are there?", "What bags are there?", (Requirement(("list_bags",)),), facts)


async def plot_velocity(box: ToolBox, probe: BagProbe) -> Task | str:
    if probe.topic(TWIST, prefer="cmd") is None:
        return "the bag has no Twist topic"
    start, end = probe.at(1 / 6), probe.at(1 / 2)
    question = f"Plot linear and angular velocity from t={start:g} s to t={end:g} s."
    plot = Requirement(("plot_timeseries",), {"start": start, "end": end})
    return Task("p02-plot-velocity", "Plot linear and angular velocity", _on(probe, question), (plot,))


async def trajectory_summary(box: ToolBox, probe: BagProbe) -> Task | str:
    if (odom := probe.topic(ODOMETRY)) is None:
        return "the bag has no odometry topic"
    summary = await box.reference("analyze_trajectory", bag=probe.bag, topic=odom)
    facts = (
        number_fact("total distance (m)", summary["distance_2d_m"], relative=0.02),
        number_fact("mean speed (m/s)", summary["mean_speed_mps"], tolerance=0.005),
        number_fact("max speed (m/s)", summary["max_speed_mps"], tolerance=0.005),
    )
    question = "Trajectory summary for the whole bag: total distance, mean and max speed."
    return _one_tool("p03-trajectory", "Trajectory summary", probe, question, "analyze_trajectory", facts)


async def plot_trajectory(box: ToolBox, probe: BagProbe) -> Task | str:
    if probe.topic(ODOMETRY) is None:
        return "the bag has no odometry topic"
    return _one_tool("p04-plot-trajectory", "Plot the trajectory", probe, "Plot the trajectory.", "plot_2d")


async def passed_near(box: ToolBox, probe: BagProbe) -> Task | str:
    if (odom := probe.topic(ODOMETRY)) is None:
        return "the bag has no odometry topic"
    path = await box.reference("analyze_trajectory", bag=probe.bag, topic=odom)  # a core tool, as search_messages
    at = probe.at(1 / 3)
    place = min(path["waypoints"] or [path["start_pose"]], key=lambda w: abs(w["time"]["offset_s"] - at))
    x, y = round(place["x"] + 0.2, 1), round(place["y"] + 0.2, 1)
    near = await box.reference(
        "search_messages",
        bag=probe.bag,
        topic=odom,
        condition="near_position",
        value={"x": x, "y": y, "radius": NEAR_RADIUS_M},
    )
    closest = near["closest"]
    facts = (
        verdict_fact("whether it passed", yes=near["total"] > 0),
        number_fact("closest distance (m)", closest["distance_m"], tolerance=0.01),
        number_fact("time of closest approach (s)", closest["time"]["offset_s"], tolerance=TIME_TOLERANCE_S),
    )
    question = f"Has the robot passed within {NEAR_RADIUS_M:g} m of ({x:g}, {y:g})? Closest approach, where and when."
    return _one_tool("p05-passed-near", "Passed within Z m of (X, Y)?", probe, question, "search_messages", facts)


async def lidar_obstacle(box: ToolBox, probe: BagProbe) -> Task | str:
    if (scan := probe.topic(LASER)) is None:
        return "the bag has no LaserScan topic"
    overall = await box.reference("analyze_lidar_scan", bag=probe.bag, topic=scan)
    within = math.ceil((float(overall["closest"]["range_m"]) + 0.15) * 10) / 10
    seen = await box.reference("analyze_lidar_scan", bag=probe.bag, topic=scan, within=within)
    first = seen["first_within"]
    facts = (
        verdict_fact("whether there is an obstacle", yes=first is not None),
        number_fact("first time within (s)", first["time"]["offset_s"], tolerance=TIME_TOLERANCE_S),
    )
    question = f"Does the lidar show an obstacle? When is the first time something is within {within:g} m?"
    return _one_tool("p06-lidar-obstacle", "Lidar obstacle within X m", probe, question, "analyze_lidar_scan", facts)


async def scan_and_histogram(box: ToolBox, probe: BagProbe) -> Task | str:
    if (scan := probe.topic(LASER)) is None or probe.topic(TWIST, prefer="cmd") is None:
        return "the bag has no LaserScan or Twist topic"
    overall = await box.reference("analyze_lidar_scan", bag=probe.bag, topic=scan)
    at = round(float(overall["closest"]["time"]["offset_s"]), 1)
    question = f"Plot the lidar scan at t={at:g} s and a histogram of cmd_vel linear x."
    requires = (Requirement(("plot_lidar_scan",), {"time": at}), Requirement(("plot_histogram",), {"path": "linear.x"}))
    return Task("p07-scan-histogram", "Lidar scan plot and cmd_vel histogram", _on(probe, question), requires)


async def tf_frames(box: ToolBox, probe: BagProbe) -> Task | str:
    if probe.topic(TF) is None:
        return "the bag has no TF topic"
    tree = await box.reference("get_tf_tree", bag=probe.bag)
    facts = tuple(word_fact(f"frame {frame}", frame) for frame in tree["frames"])
    question = "List all frames and their relationships."
    return _one_tool("p08-tf-frames", "List all frames and relationships", probe, question, "get_tf_tree", facts)


def _short(topic: str) -> str:
    """``/cmd_vel`` as the paper says it: cmd_vel."""
    return topic.strip("/").split("/")[-1]


async def filter_bag(box: ToolBox, probe: BagProbe) -> Task | str:
    cmd, odom = probe.topic(TWIST, prefer="cmd"), probe.topic(ODOMETRY)
    if cmd is None or odom is None:
        return "the bag has no Twist or odometry topic"
    question = f"Make a new bag with only {_short(cmd)} and {_short(odom)}."
    made = Requirement(("filter_bag",), {"include_topics": cmd})
    also = Requirement(("filter_bag",), {"include_topics": odom})
    return Task("p09-filter-bag", "New bag with only cmd_vel and odom", _on(probe, question), (made, also))


async def max_command(box: ToolBox, probe: BagProbe) -> Task | str:
    cmd, odom = probe.topic(TWIST, prefer="cmd"), probe.topic(ODOMETRY)
    if cmd is None or odom is None:
        return "the bag has no Twist or odometry topic"
    start, end = probe.at(1 / 3), probe.at(5 / 6)
    path_field = "twist.linear.x" if "Stamped" in probe.topics[cmd] else "linear.x"
    peak = await box.reference(
        "search_messages",
        bag=probe.bag,
        topic=cmd,
        field=path_field,
        condition="max",
        start=start,
        end=end,
        correlate_topic=odom,
    )
    match = peak["matches"][0]
    position = position_of(match["correlated"]["data"])
    facts = (
        number_fact("max commanded linear velocity (m/s)", match["value"], tolerance=0.005),
        number_fact("time of the max (s)", match["time"]["offset_s"], tolerance=TIME_TOLERANCE_S),
        number_fact("x then (m)", position["x"], tolerance=POSITION_TOLERANCE_M),
        number_fact("y then (m)", position["y"], tolerance=POSITION_TOLERANCE_M),
    )
    question = (
        f"Max commanded linear velocity between {start:g} and {end:g} s: value, time, and the robot's position then."
    )
    requires = (Requirement(("search_messages", "get_messages_in_range")),)
    return Task("p10-max-command", "Max commanded velocity, time, position", _on(probe, question), requires, facts)


PAPER_TASKS: tuple[Builder, ...] = (
    list_bags,
    plot_velocity,
    trajectory_summary,
    plot_trajectory,
    passed_near,
    lidar_obstacle,
    scan_and_histogram,
    tf_frames,
    filter_bag,
    max_command,
)
