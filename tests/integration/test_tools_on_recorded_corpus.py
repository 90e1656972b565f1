"""Every reading tool on every topic of every recorded bag answers with a result or a clear error:
never an internal error (a traceback hidden behind "Error executing tool X") and never an answer
larger than the output budget."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest
from mcp import Client

from bagmcp_cli.embedded import compose
from bagmcp_cli.settings import EmbeddedSettings
from bagmcp_gateway.mcp_front.aggregator import build_gateway_server
from tests.fixtures.mcp_client import ingested_bags, text_of

pytestmark = [pytest.mark.anyio, pytest.mark.corpus]
BUDGET_BYTES = 40_000  # 16 KB of JSON, twice (structured content and text), plus the summary line


PER_TOPIC: tuple[tuple[str, dict[str, Any]], ...] = (
    ("describe_topic", {}),
    ("get_message_at_time", {"time": "middle"}),
    ("get_messages_in_range", {"max_messages": 5}),
    ("topic_statistics", {}),
)
PER_BAG: tuple[tuple[str, dict[str, Any]], ...] = (
    ("analyze_trajectory", {}),
    ("analyze_lidar_scan", {"within": 0.5}),
    ("analyze_logs", {"limit": 5}),
    ("get_tf_tree", {}),
    ("summarize_window", {}),
)
IMAGE_TYPES = ("sensor_msgs/msg/Image", "sensor_msgs/msg/CompressedImage")


def _flight_logs(corpus: Path) -> list[str]:
    """The bag names of the corpus's flight logs and non-ROS MCAP (this sweep must reach every one)."""
    found = [*(corpus / "px4_ulog").glob("*.ulg"), *(corpus / "ardupilot").glob("*.bin")]
    assert len(found) >= 6, found
    return sorted([p.stem for p in found] + ["mcap_non_ros_profile_data_tamer"])


def _explained(tool: str, text: str) -> bool:
    return text.strip() != f"Error executing tool {tool}"


async def test_no_tool_call_on_the_corpus_fails_without_a_reason(corpus: Path, tmp_path: Path) -> None:
    composition = compose(EmbeddedSettings(corpus, tmp_path / "data"))
    unexplained: list[str] = []
    calls = 0
    async with Client(build_gateway_server(composition.upstreams), cache=None) as client:

        async def ask(label: str, tool: str, arguments: dict[str, Any]) -> None:
            nonlocal calls
            result = await client.call_tool(tool, arguments)
            calls += 1
            text = text_of(result)
            if result.is_error and not _explained(tool, text):
                unexplained.append(f"{label} {tool}")
            assert len(text) < BUDGET_BYTES, (label, tool, len(text))

        bags = await ingested_bags(client, timeout_s=180)
        statuses = {b["name"]: b["status"] for b in bags}
        flights = _flight_logs(corpus)
        assert {name: statuses.get(name) for name in flights} == dict.fromkeys(flights, "ready")  # none skipped
        for bag in bags:
            if bag["status"] != "ready":
                assert bag["error"], bag
                continue
            info = (await client.call_tool("bag_info", {"bag": bag["id"]})).structured_content
            assert info is not None
            middle = info["duration_s"] / 2
            for topic in info["topics"]:
                for tool, extra in PER_TOPIC:
                    arguments = {k: middle if v == "middle" else v for k, v in extra.items()}
                    await ask(
                        f"{bag['name']} {topic['name']}", tool, {"bag": bag["id"], "topic": topic["name"], **arguments}
                    )
                if topic["type"] in IMAGE_TYPES:
                    await ask(
                        bag["name"], "get_image_at_time", {"bag": bag["id"], "topic": topic["name"], "time": middle}
                    )
            for tool, extra in PER_BAG:
                await ask(bag["name"], tool, {"bag": bag["id"], **extra})
    composition.embedded.runner.shutdown()
    assert calls > 500
    assert unexplained == []
