"""Answers across the real recordings (../shared/data/bags, every readable format) agree with the per-bag
tools: topic counts with bag_info, TF edges with get_tf_tree, ERROR-or-worse counts with analyze_logs, and
each pose topic's rows and top speed with analyze_trajectory."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import anyio
import pytest
from mcp import Client

from bagmcp_cli.embedded import compose
from bagmcp_cli.settings import EmbeddedSettings
from bagmcp_gateway.aggregator import build_gateway_server
from tests.checks.fleet_checks import long, query
from tests.fixtures.mcp_client import call

pytestmark = [pytest.mark.anyio, pytest.mark.corpus]
LOG_TYPES = ("rosgraph_msgs/msg/Log", "rcl_interfaces/msg/Log")


async def _ready(client: Client) -> list[dict[str, Any]]:
    with anyio.fail_after(300):
        while True:
            bags: list[dict[str, Any]] = (await call(client, "list_bags", limit=500))["bags"]
            if all(b["status"] != "ingesting" for b in bags):
                return [b for b in bags if b["status"] == "ready"]
            await anyio.sleep(0.3)


def _grouped(answer: dict[str, Any], width: int) -> dict[str, dict[tuple[Any, ...], Any]]:
    found: dict[str, dict[tuple[Any, ...], Any]] = {}
    for row in answer["rows"]:
        found.setdefault(row[0], {})[tuple(row[1:width])] = row[width] if len(row) > width else True
    return found


async def _check_topics_and_tf(client: Client, bags: list[dict[str, Any]]) -> None:
    counts = _grouped(await query(client, "SELECT bag, topic, count FROM topics ORDER BY bag, topic LIMIT 100000"), 2)
    edges = _grouped(await query(client, "SELECT bag, parent, child, static, count FROM tf_edges"), 4)
    for bag in bags:
        info = await call(client, "bag_info", bag=bag["name"])
        assert counts.get(bag["name"], {}) == {(t["name"],): t["count"] for t in info["topics"]}, bag["name"]
        if any(t["type"] in ("tf2_msgs/msg/TFMessage", "tf/msg/tfMessage") for t in info["topics"]):
            tree = await long(client, "get_tf_tree", bag=bag["name"])
            wanted = {(e["parent"], e["child"], e["static"]): e["count"] for e in tree["edges"]}
            assert edges.get(bag["name"], {}) == wanted, bag["name"]


async def _check_logs_and_poses(client: Client) -> None:
    errors = _grouped(await query(client, "SELECT bag, count(*) FROM logs WHERE level_rank >= 3 GROUP BY bag"), 1)
    poses = await query(client, "SELECT bag, topic, count(*), max(speed) FROM poses GROUP BY ALL LIMIT 100000")
    logged = await query(client, f"SELECT DISTINCT bag FROM topics WHERE count > 0 AND type IN {LOG_TYPES}")
    assert len(logged["rows"]) >= 3
    for (name,) in logged["rows"]:
        logs = await long(client, "analyze_logs", bag=name, min_level="ERROR", limit=1)
        assert errors.get(name, {}).get((), 0) == logs["total"], name
    checked = 0
    for name, topic, rows, top in poses["rows"]:
        trajectory = await long(client, "analyze_trajectory", bag=name, topic=topic)
        assert rows == trajectory["samples"], (name, topic)
        if trajectory["max_speed_mps"] is not None:
            assert top >= trajectory["max_speed_mps"] * 0.999 or math.isclose(
                top, trajectory["max_speed_mps"], rel_tol=0.05
            )
            checked += 1
    assert checked >= 3  # the corpus holds odometry of several robots


async def test_answers_across_the_corpus_agree_with_the_per_bag_tools(corpus: Path, tmp_path: Path) -> None:
    composition = compose(EmbeddedSettings(corpus, tmp_path / "data"))
    try:
        async with Client(build_gateway_server(composition.upstreams), cache=None) as client:
            bags = await _ready(client)
            assert len(bags) >= 10
            total = await query(client, "SELECT count(*) FROM bags")
            assert total["rows"][0][0] == len(bags)
            await _check_topics_and_tf(client, bags)
            await _check_logs_and_poses(client)
    finally:
        composition.embedded.runner.shutdown()
