"""Answers across the real recordings (../shared/data/bags, every readable format) agree with the per-bag
tools: topic counts with bag_info, TF edges with get_tf_tree, ERROR-or-worse counts with analyze_logs, and
each pose topic's rows and top speed with analyze_trajectory (PX4 local positions included)."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import pytest
from mcp import Client

from bagmcp_cli.embedded import compose
from bagmcp_cli.settings import EmbeddedSettings
from bagmcp_gateway.mcp_front.aggregator import build_gateway_server
from bagmcp_shared.index import RECORD_TYPES
from tests.checks.fleet_checks import long, query
from tests.fixtures.mcp_client import call, ingested_bags

pytestmark = [pytest.mark.anyio, pytest.mark.corpus]
LOG_TYPES = tuple(sorted(RECORD_TYPES))  # ROS logs and flight-log texts


async def _rows(client: Client, sql: str) -> list[list[Any]]:
    """Every row of a query (its answer must not be cut: the checks below keep their answers small)."""
    answer = await query(client, sql)
    assert not answer["truncated"], sql
    return list(answer["rows"])


async def _check_topics_and_tf(client: Client, bags: list[dict[str, Any]]) -> None:
    for bag in bags:
        name = bag["name"]
        info = await call(client, "bag_info", bag=name)
        counts = await _rows(client, f"SELECT topic, count FROM topics WHERE bag = '{name}'")
        assert dict(map(tuple, counts)) == {t["name"]: t["count"] for t in info["topics"]}, name
        if any(t["type"] in ("tf2_msgs/msg/TFMessage", "tf/msg/tfMessage") for t in info["topics"]):
            tree = await long(client, "get_tf_tree", bag=name)
            edges = await _rows(client, f"SELECT parent, child, static, count FROM tf_edges WHERE bag = '{name}'")
            wanted = {(e["parent"], e["child"], e["static"]): e["count"] for e in tree["edges"]}
            assert {(p, c, s): n for p, c, s, n in edges} == wanted, name


async def _check_logs_and_poses(client: Client) -> None:
    errors = dict(map(tuple, await _rows(client, "SELECT bag, count(*) FROM logs WHERE level_rank >= 3 GROUP BY bag")))
    poses = await _rows(client, "SELECT bag, topic, count(*), max(speed) FROM poses GROUP BY ALL")
    logged = await _rows(client, f"SELECT DISTINCT bag FROM topics WHERE count > 0 AND type IN {LOG_TYPES}")
    assert len(logged) >= 3
    for (name,) in logged:
        logs = await long(client, "analyze_logs", bag=name, min_level="ERROR", limit=1)
        assert errors.get(name, 0) == logs["total"], name
    checked = 0
    for name, topic, rows, top in poses:
        trajectory = await long(client, "analyze_trajectory", bag=name, topic=topic)
        assert rows == trajectory["samples"], (name, topic)
        if trajectory["max_speed_mps"] is not None:
            assert top >= trajectory["max_speed_mps"] * 0.999 or math.isclose(
                top, trajectory["max_speed_mps"], rel_tol=0.05
            )
            checked += 1
    assert checked >= 3  # the corpus holds odometry of several robots
    assert any("local_position" in str(topic) for _, topic, _, _ in poses)  # and PX4 flights


async def test_answers_across_the_corpus_agree_with_the_per_bag_tools(corpus: Path, tmp_path: Path) -> None:
    composition = compose(EmbeddedSettings(corpus, tmp_path / "data"))
    try:
        async with Client(build_gateway_server(composition.upstreams), cache=None) as client:
            bags = [b for b in await ingested_bags(client, timeout_s=300) if b["status"] == "ready"]
            assert len(bags) >= 10
            total = await query(client, "SELECT count(*) FROM bags")
            assert total["rows"][0][0] == len(bags)
            await _check_topics_and_tf(client, bags)
            await _check_logs_and_poses(client)
    finally:
        composition.embedded.runner.shutdown()
