"""The ten tasks of the paper behind bagmcp (../shared/docs/DESIGN.md section 9), asked as an agent would ask
them, each in at most two tool calls, with answers checked against the drive bags' closed-form geometry."""

from __future__ import annotations

import base64
import io
import math
from collections.abc import Awaitable, Callable
from dataclasses import dataclass
from typing import Any

import pytest
from mcp import Client
from mcp.types import CallToolResult
from PIL import Image

from tests.fixtures import drive_lidar as lidar
from tests.fixtures import drive_scenario as drive
from tests.fixtures import drive_tf as tf
from tests.fixtures.mcp_client import text_of

Answer = dict[str, Any]
CALLS_PER_TASK = 2


@dataclass
class Agent:
    """An MCP client that counts the calls it makes (following a job with get_job counts too)."""

    client: Client
    calls: int = 0
    settle: Callable[[str], Awaitable[None]] | None = None  # waits, outside MCP, until a job has ended

    async def ask(self, tool: str, **arguments: object) -> tuple[Answer, CallToolResult]:
        self.calls += 1
        answer = await self.client.call_tool(tool, arguments)
        assert not answer.is_error, f"{tool}: {text_of(answer)}"
        assert isinstance(answer.structured_content, dict)
        content: Answer = answer.structured_content
        if "job" in content:  # a long answer: one get_job when the budget ran out
            self.calls += 1
            if self.settle is not None:
                await self.settle(content["job"]["job_id"])
            job = await self.client.call_tool("get_job", {"job_id": content["job"]["job_id"]})
            assert isinstance(job.structured_content, dict)
            assert job.structured_content["state"] == "succeeded", job.structured_content
            return job.structured_content["result"], answer
        return content.get("result", content), answer

    def task_done(self) -> None:
        assert self.calls <= CALLS_PER_TASK, f"the task took {self.calls} calls"
        self.calls = 0


def _png(answer: CallToolResult) -> Image.Image:
    image = next(c for c in answer.content if c.type == "image")
    return Image.open(io.BytesIO(base64.b64decode(image.data)))


def _series(report: Answer) -> dict[str, tuple[int, float, float]]:
    return {s["name"]: (s["points"], s["min"], s["max"]) for s in report["series"]}


def _cmd_ticks(start_s: float, end_s: float) -> list[float]:
    return [n / drive.CMD_HZ for n in range(round(start_s * drive.CMD_HZ), round(end_s * drive.CMD_HZ) + 1)]


def _closest(x: float, y: float) -> tuple[float, float]:
    """The odometry's closest approach to (x, y) and its first time, from the closed-form drive."""
    times = [n / drive.ODOM_HZ for n in range(round(drive.DURATION_S * drive.ODOM_HZ) + 1)]
    return min((math.hypot(drive.pose_at(t)[0] - x, drive.pose_at(t)[1] - y), t) for t in times)


async def bags_and_plots(agent: Agent, bag: str, names: list[str]) -> None:
    """1. What bags are there? 2. Plot linear and angular velocity from 10 s to 30 s. 4. Plot the trajectory."""
    listing, _ = await agent.ask("list_bags")
    status = {b["name"]: b["status"] for b in listing["bags"]}
    assert {name: status.get(name) for name in names} == dict.fromkeys(names, "ready")
    agent.task_done()
    report, answer = await agent.ask(
        "plot_timeseries", bag=bag, paths=["/cmd_vel.linear.x", "/cmd_vel.angular.z"], start=10, end=30
    )
    ticks = _cmd_ticks(10, 30)
    shown = _series(report)
    assert shown["/cmd_vel.linear.x"] == pytest.approx((len(ticks), 0.0, max(drive.twist_at(t)[0] for t in ticks)))
    assert shown["/cmd_vel.angular.z"] == pytest.approx((len(ticks), 0.0, max(drive.twist_at(t)[1] for t in ticks)))
    assert _png(answer).format == "PNG"
    agent.task_done()
    path, answer = await agent.ask("plot_2d", bag=bag, topic="/odom")
    xs, ys = _series(path)["/odom.pose.pose.position.x"], _series(path)["/odom.pose.pose.position.y"]
    assert (xs[1], xs[2], ys[1], ys[2]) == pytest.approx((*drive.X_EXTENT_M, *drive.Y_EXTENT_M), abs=1e-6)
    assert _png(answer).format == "PNG"
    agent.task_done()


async def motion_and_places(agent: Agent, bag: str) -> None:
    """3. Trajectory summary. 5. Has the robot passed within 0.5 m of (2, 0.3)? And of (1, 1)?"""
    summary, _ = await agent.ask("analyze_trajectory", bag=bag)
    assert summary["distance_2d_m"] == pytest.approx(drive.TOTAL_DISTANCE_M, rel=0.01)
    assert summary["mean_speed_mps"] == pytest.approx(drive.TOTAL_DISTANCE_M / drive.PATH_DURATION_S, rel=0.01)
    assert summary["max_speed_mps"] == pytest.approx(drive.MAX_SPEED_MPS, rel=0.02)
    agent.task_done()
    for x, y, passed in ((2.0, 0.3, True), (1.0, 1.0, False)):
        near, _ = await agent.ask(
            "search_messages", bag=bag, topic="/odom", condition="near_position", value={"x": x, "y": y, "radius": 0.5}
        )
        distance, when = _closest(x, y)
        assert (near["total"] > 0) is passed
        assert near["closest"]["distance_m"] == pytest.approx(distance, abs=1e-6)
        assert near["closest"]["time"]["offset_s"] == pytest.approx(when)
        assert (near["closest"]["x"], near["closest"]["y"]) == pytest.approx(drive.pose_at(when)[:2], abs=1e-6)
        agent.task_done()


async def lidar_and_frames(agent: Agent, bag: str) -> None:
    """6. When is something first within 0.5 m? 7. The scan at 25.6 s and a histogram of cmd_vel linear x.
    8. All frames and their relationships."""
    seen, _ = await agent.ask("analyze_lidar_scan", bag=bag, within=lidar.NEAR_RANGE_M)
    assert seen["first_within"]["time"]["offset_s"] == pytest.approx(lidar.FIRST_WITHIN_0_5_S, abs=0.1)
    assert seen["first_within"]["range_m"] < lidar.NEAR_RANGE_M
    agent.task_done()
    scan, answer = await agent.ask("plot_lidar_scan", bag=bag, time=lidar.CLOSEST_S)
    assert scan["series"][0]["min"] == pytest.approx(lidar.CLOSEST_RANGE_M, abs=1e-3)
    assert _png(answer).format == "PNG"
    histogram, answer = await agent.ask("plot_histogram", bag=bag, path="/cmd_vel.linear.x")
    assert _series(histogram)["/cmd_vel.linear.x"][0] == len(_cmd_ticks(0, drive.DURATION_S))
    assert _png(answer).format == "PNG"
    agent.task_done()
    tree, _ = await agent.ask("get_tf_tree", bag=bag)
    assert set(tree["frames"]) == set(tf.FRAMES)
    assert {(e["parent"], e["child"], e["static"]) for e in tree["edges"]} == {
        (e.parent, e.child, e.static) for e in tf.EDGES
    }
    agent.task_done()


async def cut_and_peak(agent: Agent, bag: str) -> None:
    """9. A new bag with only cmd_vel and odom. 10. The max commanded linear velocity between 20 and 50 s, when,
    and where the robot was then."""
    made, _ = await agent.ask("filter_bag", bag=bag, include_topics=["/cmd_vel", "/odom"])
    info, _ = await agent.ask("bag_info", bag=made["bag_id"])
    topics = {t["name"]: t["count"] for t in info["topics"]}
    every = {"/cmd_vel": len(_cmd_ticks(0, drive.DURATION_S)), "/odom": len(drive.tick_offsets_ns(drive.ODOM_HZ))}
    assert made["counts"] == every
    assert topics == every
    agent.task_done()
    peak, _ = await agent.ask(
        "search_messages", bag=bag, topic="/cmd_vel", condition="max", start=20, end=50, correlate_topic="/odom"
    )
    window = _cmd_ticks(20, 50)
    top = max(drive.twist_at(t)[0] for t in window)
    first = min(t for t in window if drive.twist_at(t)[0] == top)
    match = peak["matches"][0]
    assert (match["value"], match["time"]["offset_s"]) == pytest.approx((top, first))
    position = match["correlated"]["data"]["pose.pose.position"]
    assert (position["x"], position["y"]) == pytest.approx(drive.pose_at(first)[:2], abs=1e-6)
    agent.task_done()


async def check_paper_tasks(
    client: Client, bag: str, names: list[str], *, settle: Callable[[str], Awaitable[None]] | None = None
) -> None:
    agent = Agent(client, settle=settle)
    await bags_and_plots(agent, bag, names)
    await motion_and_places(agent, bag)
    await lidar_and_frames(agent, bag)
    await cut_and_peak(agent, bag)
