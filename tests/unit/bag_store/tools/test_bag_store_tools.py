"""Every bag-store tool, called through an in-memory MCP client on the bag-store's own server."""

from __future__ import annotations

import json

import pytest
from mcp import Client
from mcp.types import TextContent

from tests.checks.first_tools import check_first_tools
from tests.checks.search_checks import check_search, finished
from tests.fixtures import scenario as sc
from tests.fixtures.inprocess import InProcess
from tests.fixtures.mcp_client import call, call_error
from tests.unit.conftest import SCENARIO_NAMES

pytestmark = pytest.mark.anyio


async def test_the_catalog_and_message_tools_answer_on_three_formats(served: InProcess) -> None:
    async with Client(served.service("bag-store"), cache=None) as client:
        await check_first_tools(client, SCENARIO_NAMES)


async def test_search_answers_on_three_formats(served: InProcess) -> None:
    async with Client(served.service("bag-store"), cache=None) as client:
        await check_search(client, SCENARIO_NAMES)


async def test_filter_bag_makes_a_bag_that_bag_info_confirms(served: InProcess) -> None:
    async with Client(served.service("bag-store"), cache=None) as client:
        answer = await call(client, "filter_bag", bag="scenario_mcap", include_topics=["/cmd_vel"], name="cmd-unit")
        result = await finished(client, answer)
        assert result["counts"] == {"/cmd_vel": sc.COUNTS["/cmd_vel"]}
        info = await call(client, "bag_info", bag="cmd-unit")
        assert {t["name"]: t["count"] for t in info["topics"]} == {"/cmd_vel": sc.COUNTS["/cmd_vel"]}


async def test_an_argument_the_tool_does_not_have_is_an_error_naming_the_valid_ones(served: InProcess) -> None:
    async with Client(served.service("bag-store"), cache=None) as client:
        text = await call_error(client, "get_messages_in_range", bag="scenario", topic="/odom", max_message=5)
        assert "max_message" in text
        assert "max_messages" in text


async def test_every_tool_declares_its_annotations_and_output_schema(served: InProcess) -> None:
    async with Client(served.service("bag-store"), cache=None) as client:
        tools = (await client.list_tools()).tools
    assert {t.name for t in tools} == {
        "list_bags",
        "bag_info",
        "describe_topic",
        "get_message_at_time",
        "get_messages_in_range",
        "search_messages",
        "filter_bag",
        "query_bags",
        "find_bags",
    }
    for tool in tools:
        hints = tool.annotations
        assert hints is not None, tool.name
        assert None not in (hints.read_only_hint, hints.destructive_hint, hints.idempotent_hint, hints.open_world_hint)
        assert tool.output_schema is not None, tool.name


async def test_a_thousand_points_of_two_fields_fit_the_answer_budget(served_drive: InProcess) -> None:
    async with Client(served_drive.service("bag-store"), cache=None) as client:
        answer = await client.call_tool(
            "get_messages_in_range",
            {
                "bag": "drive_mcap",
                "topic": "/odom",
                "fields": ["pose.pose.position.x", "pose.pose.position.y"],
                "layout": "columns",
            },
        )
    data = answer.structured_content
    assert data is not None
    assert data["returned"] >= 900
    assert len(json.dumps(data, separators=(",", ":"))) <= 16_000
    assert max(data["columns"]["pose.pose.position.x"]) == pytest.approx(4.0, abs=1e-5)


async def test_filter_bag_says_when_the_bag_existed_already_under_another_name(served: InProcess) -> None:
    async with Client(served.service("bag-store"), cache=None) as client:
        asked = {"bag": "scenario", "include_topics": ["/cmd_vel"]}  # one ROS 1 file: its bytes hold no name
        first = await finished(client, await call(client, "filter_bag", **asked, name="cmd-first"))
        again = await client.call_tool("filter_bag", {**asked, "name": "cmd-second"})
    assert first["created"] is True
    assert first["note"] is None
    assert again.structured_content is not None
    second = again.structured_content["result"]
    assert (second["created"], second["name"], second["bag_id"]) == (False, "cmd-first", first["bag_id"])
    assert "'cmd-second' was not used" in second["note"]
    assert "cmd-first" in second["note"]
    text = again.content[0]
    assert isinstance(text, TextContent)
    assert text.text.startswith("bag cmd-first")
    assert "the name 'cmd-second' was not used" in text.text


async def test_an_absurd_time_is_an_error_that_says_what_times_are_accepted(served: InProcess) -> None:
    async with Client(served.service("bag-store"), cache=None) as client:
        text = await call_error(client, "get_message_at_time", bag="scenario", topic="/odom", time=1e308)
    assert text.endswith("time 1e+308 is out of range; give seconds from the bag start, epoch seconds or ISO-8601")


async def test_a_page_cursor_altered_or_used_for_another_request_is_refused(served: InProcess) -> None:
    window: dict[str, object] = {"bag": "scenario", "topic": "/cmd_vel", "start": 2.0, "end": 3.0}
    async with Client(served.service("bag-store"), cache=None) as client:
        page = await call(client, "get_messages_in_range", **window, max_messages=4)
        cursor = str(page["next_cursor"])
        stamp, skip, total, position = cursor.split(":")[:4]
        assert total == "11"
        forged = [f"{stamp}:{skip}:-1:{position}", f"{stamp}:{skip}:5:{position}", cursor.replace(f":{total}:", ":5:")]
        elsewhere: list[dict[str, object]] = [{"topic": "/odom"}, {"bag": "scenario_mcap"}, {"every": 2}, {"end": 2.9}]
        refusals = [await call_error(client, "get_messages_in_range", **window, cursor=c) for c in forged]
        refusals += [
            await call_error(client, "get_messages_in_range", **{**window, **e}, cursor=cursor) for e in elsewhere
        ]
        for refusal in refusals:
            assert "this cursor is not one get_messages_in_range returned for this bag, topic" in refusal
            assert "call again without cursor" in refusal
        following = await call(client, "get_messages_in_range", **window, cursor=cursor)
    assert (following["total"], following["returned"]) == (11, 7)
