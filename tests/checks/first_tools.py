"""The assertions issue 3 asks of every way of running: the first five tools on three formats.

Each mode's test (distributed stack, embedded HTTP, stdio) connects a real MCP client and
calls ``check_first_tools`` with the names its three scenario bags got.
"""

from __future__ import annotations

import pytest
from mcp import Client

from tests.fixtures import scenario as sc
from tests.fixtures.mcp_client import call, call_error

ISO_AT_5S = "2023-11-14T22:13:25Z"  # START_NS + 5 s


async def check_listing(client: Client, names: list[str]) -> None:
    listing = await call(client, "list_bags")
    bags = {b["name"]: b for b in listing["bags"]}
    for name in names:
        assert bags[name]["status"] == "ready"
        assert bags[name]["message_count"] == sum(sc.COUNTS.values())
        assert bags[name]["topic_count"] == len(sc.COUNTS)


async def check_bag_info(client: Client, name: str) -> None:
    info = await call(client, "bag_info", bag=name)
    assert {t["name"]: t["count"] for t in info["topics"]} == sc.COUNTS
    assert info["duration_s"] == pytest.approx(sc.DURATION_S - 1 / sc.ODOM_HZ)
    assert info["start"]["stamp_s"] == pytest.approx(sc.START_NS / 1e9)
    odom = next(t for t in info["topics"] if t["name"] == sc.ODOM_TOPIC)
    assert odom["rate_hz"] == pytest.approx(sc.ODOM_HZ)
    assert odom["header_rate_hz"] == pytest.approx(sc.ODOM_HZ)
    cmd = next(t for t in info["topics"] if t["name"] == sc.CMD_TOPIC)
    assert cmd["header_rate_hz"] is None  # geometry_msgs/Twist has no header


async def check_describe_topic(client: Client, name: str) -> None:
    described = await call(client, "describe_topic", bag=name, topic="odom")
    assert described["type"] == "nav_msgs/msg/Odometry"
    fields = {f["path"]: f for f in described["fields"]}
    assert fields["twist.twist.linear.x"]["unit"] == "m/s"
    assert fields["pose.pose.orientation.yaw"]["unit"] == "rad"
    assert described["sample"]["child_frame_id"] == "base_link"


async def check_message_at_time(client: Client, name: str) -> None:
    fields = ["pose.pose.position.x", "pose.pose.position.y"]
    by_offset = await call(client, "get_message_at_time", bag=name, topic="/odom", time=5.0, fields=fields)
    by_epoch = await call(
        client, "get_message_at_time", bag=name, topic="/odom", time=sc.START_NS / 1e9 + 5, fields=fields
    )
    by_iso = await call(client, "get_message_at_time", bag=name, topic="/odom", time=ISO_AT_5S, fields=fields)
    assert by_offset["message"] == by_epoch["message"] == by_iso["message"]
    x, y, _ = sc.pose_at(5.0)
    data = by_offset["message"]["data"]
    assert data["pose.pose.position.x"] == pytest.approx(x)
    assert data["pose.pose.position.y"] == pytest.approx(y)
    assert by_offset["message"]["time"]["offset_s"] == pytest.approx(5.0)
    near = await call(client, "get_message_at_time", bag=name, topic="/cmd_vel", time=2.04)
    assert near["delta_s"] == pytest.approx(-0.04)
    assert near["message"]["time"]["offset_s"] == pytest.approx(2.0)


async def check_messages_in_range(client: Client, name: str) -> None:
    window = {"bag": name, "topic": "/cmd_vel", "start": 2.0, "end": 3.0, "fields": ["linear.x"]}
    page = await call(client, "get_messages_in_range", **window, max_messages=4)
    assert page["total"] == 11
    assert page["returned"] == 4
    assert page["truncated"] is True
    speeds = [m["data"]["linear.x"] for m in page["messages"]]
    assert speeds == pytest.approx([sc.cmd_speed_at(2.0)] * 4)
    following = await call(client, "get_messages_in_range", **window, max_messages=20, cursor=page["next_cursor"])
    offsets = [m["offset_s"] for m in following["messages"]]
    assert offsets == pytest.approx([2.4 + i / 10 for i in range(7)])
    assert following["truncated"] is False
    assert following["time_base"].startswith("log time, s from the bag start ")
    assert set(following["messages"][0]) == {"offset_s", "data"}  # the time base is said once per answer


async def check_clear_errors(client: Client, name: str) -> None:
    unknown = await call_error(client, "bag_info", bag=name + "-nope")
    assert "did you mean" in unknown
    assert name in unknown
    no_topic = await call_error(client, "get_message_at_time", bag=name, topic="/odometry", time=1.0)
    assert "/odom" in no_topic
    assert "/cmd_vel" in no_topic
    outside = await call_error(client, "get_message_at_time", bag=name, topic="/odom", time=500.0)
    assert "outside the bag" in outside
    bad_path = await call_error(client, "get_messages_in_range", bag=name, topic="/odom", fields=["pose.pos.x"])
    assert "pose.pose.position.x" in bad_path


async def check_first_tools(client: Client, names: list[str]) -> None:
    """Everything issue 3 requires of list_bags, bag_info, describe_topic and the two readers."""
    await check_listing(client, names)
    for name in names:
        await check_bag_info(client, name)
        await check_describe_topic(client, name)
        await check_message_at_time(client, name)
        await check_messages_in_range(client, name)
        await check_columns_and_thinning(client, name)
    await check_clear_errors(client, names[0])


async def check_columns_and_thinning(client: Client, name: str) -> None:
    """layout=columns: 1,000 points of two fields fit the budget; thinning keeps each field's extremes."""
    fields = ["pose.pose.position.x", "twist.twist.linear.x"]
    columns = await call(client, "get_messages_in_range", bag=name, topic="/odom", fields=fields, layout="columns")
    assert columns["total"] == sc.COUNTS[sc.ODOM_TOPIC]
    assert len(columns["t"]) == len(columns["columns"]["pose.pose.position.x"]) == columns["returned"]
    assert columns["t"][0] == pytest.approx(0.0)
    xs = [sc.pose_at(t)[0] for t in sc.ticks(sc.ODOM_HZ)]
    thin = await call(
        client, "get_messages_in_range", bag=name, topic="/odom", fields=fields, layout="columns", max_points=20
    )
    assert thin["downsampled"] is True
    assert thin["returned"] <= 20
    assert min(thin["columns"]["pose.pose.position.x"]) == pytest.approx(min(xs), rel=1e-4)  # 5 digits kept
    assert max(thin["columns"]["pose.pose.position.x"]) == pytest.approx(max(xs), rel=1e-4)
    every = await call(client, "get_messages_in_range", bag=name, topic="/odom", every=50, max_messages=100)
    assert every["returned"] == sc.COUNTS[sc.ODOM_TOPIC] // 50
    assert every["messages"][1]["offset_s"] == pytest.approx(50 / sc.ODOM_HZ)
    text = await call_error(client, "get_messages_in_range", bag=name, topic="/odom", layout="columns")
    assert "fields" in text
    await check_max_points_is_honoured_or_refused(client, name, fields)


async def check_max_points_is_honoured_or_refused(client: Client, name: str, fields: list[str]) -> None:
    """max_points without layout=columns thins the fields in columns and says so; without fields it is refused."""
    thin = await call(client, "get_messages_in_range", bag=name, topic="/odom", fields=fields, max_points=50)
    assert thin["total"] == sc.COUNTS[sc.ODOM_TOPIC]
    assert 2 < thin["returned"] <= 50
    assert thin["downsampled"] is True
    assert thin["notes"][0] == "max_points thins numeric fields, so this answer is in layout=columns"
    refused = await call_error(client, "get_messages_in_range", bag=name, topic="/odom", max_points=50)
    assert "max_points (it thins numeric fields, in layout=columns) needs `fields`" in refused
    assert "every=N" in refused
