"""Every reading tool on every topic of every recorded bag answers with a result or a clear error:
never an internal error (a traceback hidden behind "Error executing tool X") and never an answer
larger than the output budget."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import anyio
import pytest
from mcp import Client

from bagmcp_gateway.aggregator import build_gateway_server
from bagmcp_gateway.embedded import embed
from tests.fixtures.mcp_client import call, text_of

pytestmark = [pytest.mark.anyio, pytest.mark.corpus]
BUDGET_BYTES = 40_000  # 16 KB of JSON, twice (structured content and text), plus the summary line


async def _ready(client: Client) -> list[dict[str, Any]]:
    with anyio.fail_after(180):
        while True:
            bags: list[dict[str, Any]] = (await call(client, "list_bags", limit=500))["bags"]
            if all(b["status"] != "ingesting" for b in bags):
                return bags
            await anyio.sleep(0.2)


async def test_no_tool_call_on_the_corpus_fails_without_a_reason(corpus: Path, tmp_path: Path) -> None:
    embedded = embed(corpus, tmp_path / "data")
    unexplained: list[str] = []
    calls = 0
    async with Client(build_gateway_server(embedded.upstreams), cache=None) as client:
        for bag in await _ready(client):
            if bag["status"] != "ready":
                assert bag["error"], bag
                continue
            info = (await client.call_tool("bag_info", {"bag": bag["id"]})).structured_content
            assert info is not None
            for topic in info["topics"]:
                for tool, extra in (
                    ("describe_topic", {}),
                    ("get_message_at_time", {"time": info["duration_s"] / 2}),
                    ("get_messages_in_range", {"max_messages": 5}),
                ):
                    result = await client.call_tool(tool, {"bag": bag["id"], "topic": topic["name"], **extra})
                    calls += 1
                    text = text_of(result)
                    if result.is_error and text.strip() == f"Error executing tool {tool}":
                        unexplained.append(f"{bag['name']} {topic['name']} {tool}")
                    assert len(text) < BUDGET_BYTES, (bag["name"], topic["name"], tool, len(text))
    embedded.runner.shutdown()
    assert calls > 300
    assert unexplained == []
