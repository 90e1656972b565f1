"""Harder tasks of ours, beyond the paper: logs at a level, a transform between two frames at a time, an image,
what happened in a window, and a question across bags. References come from the tools, as for the paper's."""

from __future__ import annotations

from bagmcp_lab.tasks.bag_probe import IMAGE, LASER, LOGS, ODOMETRY, TF, BagProbe
from bagmcp_lab.tasks.model import Fact, Requirement, Task, number_fact, word_fact
from bagmcp_lab.tasks.paper import Builder
from bagmcp_lab.toolbox import ToolBox

SUITE = "ours"


def _on(probe: BagProbe, question: str) -> str:
    return f"{question} (bag: {probe.bag})"


async def warnings(box: ToolBox, probe: BagProbe) -> Task | str:
    if probe.topic(LOGS) is None:
        return "the bag has no log topic"
    logs = await box.reference("analyze_logs", bag=probe.bag, min_level="WARN", limit=1)
    nodes = sorted((logs.get("summary") or {}).get("by_node", {}))
    facts: tuple[Fact, ...] = (number_fact("WARN-or-worse records", logs["total"]),)
    facts += tuple(word_fact(f"node {node}", node.lstrip("/")) for node in nodes[:5])
    question = "Which log messages at WARN level or above are in the bag? How many, and from which nodes?"
    return Task(
        "o11-warnings", "Logs at WARN or above", _on(probe, question), (Requirement(("analyze_logs",)),), facts, SUITE
    )


async def transform(box: ToolBox, probe: BagProbe) -> Task | str:
    if probe.topic(TF) is None:
        return "the bag has no TF topic"
    tree = await box.reference("get_tf_tree", bag=probe.bag)
    moving = [e for e in tree["edges"] if not e["static"]]
    if not tree["roots"] or not moving:
        return "the bag's TF tree has no moving frame"
    target, source, at = str(tree["roots"][0]), str(moving[0]["child"]), probe.at(1 / 6)
    found = await box.reference("lookup_transform", bag=probe.bag, target_frame=target, source_frame=source, time=at)
    x, y, _z = found["translation_m"]
    facts = (
        number_fact(f"x of {source} in {target} (m)", x, tolerance=0.01),
        number_fact(f"y of {source} in {target} (m)", y, tolerance=0.01),
        number_fact("yaw (deg)", found["yaw_deg"], tolerance=0.5),
    )
    question = f"Where is {source} in the {target} frame at t={at:g} s? Give x, y and yaw."
    requires = (Requirement(("lookup_transform",), {"source_frame": source}),)
    return Task("o12-transform", "Transform between two frames at a time", _on(probe, question), requires, facts, SUITE)


async def image(box: ToolBox, probe: BagProbe) -> Task | str:
    if (topic := probe.topic(IMAGE, prefer="rgb")) is None:
        return "the bag has no image topic"
    at = probe.first_s[topic]
    seen = await box.reference("get_image_at_time", bag=probe.bag, topic=topic, time=at)
    facts = (
        number_fact("width (px)", seen["width"]),
        number_fact("height (px)", seen["height"]),
    )
    question = f"Show me the image on {topic} at t={at:g} s. What is its size in pixels?"
    requires = (Requirement(("get_image_at_time",), {"topic": topic}),)
    return Task("o13-image", "An image and its size", _on(probe, question), requires, facts, SUITE)


async def window(box: ToolBox, probe: BagProbe) -> Task | str:
    if probe.topic(ODOMETRY) is None:
        return "the bag has no odometry topic"
    start, end = probe.at(1 / 6), probe.at(1 / 3)
    summary = await box.reference("summarize_window", bag=probe.bag, start=start, end=end)
    if summary.get("motion") is None:
        return "no motion found in the window"
    facts = (
        number_fact("distance moved (m)", summary["motion"]["distance_m"], tolerance=0.05),
        number_fact("WARN-or-worse records", sum(summary["warnings"].values())),
    )
    question = (
        f"What happened between {start:g} and {end:g} s? How far did the robot move, and how many warnings were logged?"
    )
    requires = (Requirement(("summarize_window", "analyze_trajectory")),)
    return Task("o14-window", "What happened in a window", _on(probe, question), requires, facts, SUITE)


async def across_bags(box: ToolBox, probe: BagProbe) -> Task | str:
    """Counted on the LaserScan topic, which the paper's filter task (cmd_vel and odom only) never copies, so
    the answer does not change while the suite runs."""
    if (scan := probe.topic(LASER)) is None:
        return "the bag has no LaserScan topic"
    listing = await box.reference("list_bags", limit=500)
    total = 0
    for bag in (b for b in listing["bags"] if b["status"] == "ready"):
        info = await box.reference("bag_info", bag=bag["id"])
        total += sum(int(t["count"]) for t in info["topics"] if t["name"] == scan)
    question = f"How many {scan} messages are there across all our bags together?"
    requires = (Requirement(("bag_info", "query_bags")),)
    facts = (number_fact(f"{scan} messages in all bags", total),)
    return Task("o15-across-bags", "A question across bags", question, requires, facts, SUITE)


OUR_TASKS: tuple[Builder, ...] = (warnings, transform, image, window, across_bags)
