"""Assertions of issue 4 for search_messages and jobs, run against every way of serving.

Answers may come back finished or as a job (when a mode runs with a small time budget);
``finished`` follows the job with get_job either way.
"""

from __future__ import annotations

import math
from typing import Any

import anyio
import pytest
from mcp import Client

from tests.fixtures import scenario as sc
from tests.fixtures.mcp_client import call, call_error, text_of

Answer = dict[str, Any]


async def finished(client: Client, answer: Answer, *, timeout_s: float = 60) -> Answer:
    """The result of a long tool's answer, following its job until it ends."""
    if "result" in answer:
        assert "job" not in answer, answer  # an answer holds the result or the job, never both
        return answer["result"]  # type: ignore[no-any-return]
    job_id = answer["job"]["job_id"]
    with anyio.fail_after(timeout_s):
        while True:
            job = await call(client, "get_job", job_id=job_id)
            if job["state"] == "succeeded":
                return job["result"]  # type: ignore[no-any-return]
            assert job["state"] in ("queued", "running"), job
            await anyio.sleep(0.1)


async def search(client: Client, **arguments: object) -> Answer:
    return await finished(client, await call(client, "search_messages", **arguments))


def _closest_to(x: float, y: float) -> tuple[float, float]:
    """Independent answer: the closest approach of the scenario's odometry to (x, y) and its time."""
    return min((math.hypot(sc.pose_at(t)[0] - x, sc.pose_at(t)[1] - y), t) for t in sc.ticks(sc.ODOM_HZ))


async def check_near_position(client: Client, bag: str) -> None:
    distance, when = _closest_to(2.0, 2.0)
    hit = await search(client, bag=bag, topic="/odom", condition="near_position", value={"x": 2, "y": 2, "radius": 0.5})
    assert hit["total"] > 0
    assert hit["closest"]["distance_m"] == pytest.approx(distance, abs=1e-6)
    assert hit["closest"]["time"]["offset_s"] == pytest.approx(when)
    assert all(m["distance_m"] <= 0.5 for m in hit["matches"])
    far_distance, far_when = _closest_to(10.0, 10.0)
    miss = await search(client, bag=bag, topic="/odom", condition="near_position", value="10,10,1")
    assert miss["total"] == 0
    assert miss["matches"] == []
    assert miss["closest"]["distance_m"] == pytest.approx(far_distance, abs=1e-6)
    assert miss["closest"]["time"]["offset_s"] == pytest.approx(far_when)


async def check_text_and_numbers(client: Client, bag: str) -> None:
    log = await search(client, bag=bag, topic="/rosout", condition="contains", value="OBSTACLE")
    assert log["total"] == 1
    assert log["matches"][0]["value"] == "obstacle detected ahead"
    assert log["matches"][0]["time"]["offset_s"] == pytest.approx(6.0)
    pattern = await search(client, bag=bag, topic="/rosout", condition="regex", value=r"battery below \d+ percent")
    assert [m["time"]["offset_s"] for m in pattern["matches"]] == pytest.approx([2.5])
    lidar = await search(client, bag=bag, topic="/scan", condition="less_than", value=0.5)
    assert lidar["field"] == "min_range"  # the field tested is stated even when it was the default
    assert lidar["total"] == round((sc.DURATION_S - sc.OBSTACLE_FROM_S) * sc.SCAN_HZ)
    assert lidar["matches"][0]["time"]["offset_s"] == pytest.approx(sc.OBSTACLE_FROM_S)
    assert lidar["matches"][0]["value"] == pytest.approx(sc.OBSTACLE_RANGE_M)
    fast = await search(client, bag=bag, topic="/cmd_vel", condition="greater_than", value=0.9, field="linear.x")
    assert fast["total"] == 10
    assert fast["matches"][0]["time"]["offset_s"] == pytest.approx(9.0)
    band = await search(client, bag=bag, topic="/cmd_vel", condition="between", value=[0.59, 0.66])
    assert band["total"] == 20
    assert sorted({round(m["value"], 6) for m in band["matches"]}) == [0.6, 0.65]
    exists = await search(client, bag=bag, topic="/scan", condition="field_exists", field="ranges[359]")
    assert exists["total"] == sc.COUNTS["/scan"]
    beyond = await search(client, bag=bag, topic="/scan", condition="field_exists", field="ranges[360]")
    assert beyond["total"] == 0


async def check_correlation(client: Client, bag: str) -> None:
    fast = await search(
        client,
        bag=bag,
        topic="/cmd_vel",
        condition="greater_than",
        value=0.9,
        correlate_topic="/odom",
        correlate_tolerance_s=0.02,
    )
    for match in fast["matches"]:
        partner = match["correlated"]
        assert partner["topic"] == "/odom"
        assert partner["delta_s"] == pytest.approx(0.0)
        x, _, _ = sc.pose_at(match["time"]["offset_s"])
        assert partner["data"]["pose.pose.position"]["x"] == pytest.approx(x)
        assert set(partner["data"]) == {
            "pose.pose.position",
            "pose.pose.orientation.yaw",
            "twist.twist.linear",
            "twist.twist.angular.z",
        }  # what answers "where and how fast", not the covariances
    whole = await search(
        client, bag=bag, topic="/cmd_vel", condition="greater_than", value=0.9, correlate_topic="/odom.", limit=1
    )
    assert whole["matches"][0]["correlated"]["data"]["pose"]["covariance"][0] == 0  # "/odom." asks for it whole
    picked = await search(
        client, bag=bag, topic="/cmd_vel", condition="greater_than", value=0.9, correlate_topic="/odom.twist", limit=1
    )
    assert list(picked["matches"][0]["correlated"]["data"]) == ["twist"]


async def check_extremes(client: Client, bag: str) -> None:
    """max/min: the messages holding the window's peak, here with the pose at the first of them."""
    window = [t for t in sc.ticks(sc.CMD_HZ) if 2.0 <= t <= 6.0]
    peak = max(sc.cmd_speed_at(t) for t in window)
    at_peak = [t for t in window if sc.cmd_speed_at(t) == peak]
    top = await search(
        client, bag=bag, topic="/cmd_vel", condition="max", start=2, end=6, correlate_topic="/odom", limit=1
    )
    assert (top["field"], top["total"]) == ("linear.x", len(at_peak))
    first = top["matches"][0]
    assert first["value"] == pytest.approx(peak)
    assert first["time"]["offset_s"] == pytest.approx(at_peak[0])
    x, y, _ = sc.pose_at(at_peak[0])
    position = first["correlated"]["data"]["pose.pose.position"]
    assert (position["x"], position["y"]) == pytest.approx((x, y))
    said = text_of(await client.call_tool("search_messages", {"bag": bag, "topic": "/cmd_vel", "condition": "max"}))
    top_all = max(sc.cmd_speed_at(t) for t in sc.ticks(sc.CMD_HZ))
    assert said.startswith(f"max linear.x = {top_all:.6g} first at ")  # the peak first, then how many share it
    low = await search(client, bag=bag, topic="/cmd_vel", condition="min", field="linear.x")
    assert low["matches"][0]["value"] == pytest.approx(min(sc.cmd_speed_at(t) for t in sc.ticks(sc.CMD_HZ)))
    assert "leave out `value`" in await call_error(
        client, "search_messages", bag=bag, topic="/cmd_vel", condition="max", value=1
    )


async def check_search_errors(client: Client, bag: str) -> None:
    unknown = await call_error(client, "search_messages", bag=bag, topic="/odom", condition="similar", value=1)
    assert "near_position" in unknown
    wrong = await call_error(client, "search_messages", bag=bag, topic="/odom", condition="between", value=3)
    assert "[low, high]" in wrong
    no_number = await call_error(client, "search_messages", bag=bag, topic="/tf", condition="greater_than", value=1)
    assert "pass `field`" in no_number


async def check_search(client: Client, bags: list[str]) -> None:
    for bag in bags:
        await check_near_position(client, bag)
    await check_text_and_numbers(client, bags[0])
    await check_correlation(client, bags[-1])
    await check_extremes(client, bags[1])
    await check_search_errors(client, bags[0])
    for bag in (bags[0], bags[-1]):  # ROS 1 and ROS 2 levels
        await check_log_levels_by_name(client, bag)


async def check_slow_search_becomes_a_job_with_progress(client: Client, bag: str) -> None:
    """Needs a server whose time budget is shorter than a text search over ``bag`` (/chatter)."""
    seen: list[float] = []

    async def on_progress(progress: float, total: float | None, message: str | None) -> None:
        seen.append(progress)

    arguments = {
        "bag": bag,
        "topic": "/chatter",
        "condition": "equals",
        "field": "data",
        "value": "hello 123456",
    }
    result = await client.call_tool("search_messages", arguments, progress_callback=on_progress)
    answer = result.structured_content
    assert answer is not None
    assert not result.is_error
    assert "result" not in answer
    assert answer["job"]["state"] in ("queued", "running")
    assert seen, "no progress notification reached the client"
    final = await finished(client, answer)
    assert final["total"] == 1
    assert final["matches"][0]["value"] == "hello 123456"
    assert final["matches"][0]["time"]["offset_s"] == pytest.approx(123.456)


async def check_cancel_stops_a_running_job(client: Client, bag: str) -> None:
    answer = await call(client, "search_messages", bag=bag, topic="/chatter", condition="regex", value=r"hello \d+5$")
    job_id = answer["job"]["job_id"]
    cancelled = await call(client, "cancel_job", job_id=job_id)
    assert cancelled["job_id"] == job_id
    with anyio.fail_after(30):
        while (job := await call(client, "get_job", job_id=job_id))["state"] not in (
            "cancelled",
            "succeeded",
        ):
            await anyio.sleep(0.1)
    assert job["state"] == "cancelled"
    assert job["result"] is None


async def check_log_levels_by_name(client: Client, bag: str) -> None:
    """Level names work on either ROS version's numbers; matches carry level name, node and text."""
    errors = await search(client, bag=bag, topic="/rosout", condition="equals", value="ERROR")
    assert errors["field"] == "level"
    assert errors["total"] == 1
    details = errors["matches"][0]["details"]
    assert details == {"level": "ERROR", "node": "/planner", "text": "obstacle detected ahead"}
    serious = await search(client, bag=bag, topic="/rosout", condition="greater_than", value="info")
    assert serious["total"] == 2
    assert {m["details"]["level"] for m in serious["matches"]} == {"WARN", "ERROR"}
    assert "DEBUG, INFO, WARN" in await call_error(
        client, "search_messages", bag=bag, topic="/rosout", condition="greater_than", value="LOUD"
    )
