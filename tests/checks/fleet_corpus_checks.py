"""Answers across the real recordings (../shared/data/bags, every readable format) checked against the per-bag
tools on any server holding them: topic counts with bag_info, TF edges with get_tf_tree, ERROR-or-worse counts
with analyze_logs, each pose topic's rows and top speed with analyze_trajectory (PX4 local positions included),
and find_bags' `log at or above ERROR` and `has topic` with the same tools' answers.

Every question names the bags it is about (``bag IN (...)``, find_bags' matches kept to ``names``): the
session's stack serves other tests' bags too."""

from __future__ import annotations

import math
from typing import Any

from mcp import Client

from bagmcp_shared.index import RECORD_TYPES
from tests.checks.fleet_checks import long, query
from tests.fixtures.mcp_client import call

LOG_TYPES = tuple(sorted(RECORD_TYPES))  # ROS logs and flight-log texts
TF_TYPES = ("tf2_msgs/msg/TFMessage", "tf/msg/tfMessage")
HAS_TOPIC = "/rosout"  # ROS 1 and 2 bags have it, some empty, and out.bag spells it "rosout"


async def _rows(client: Client, sql: str) -> list[list[Any]]:
    """Every row of a query (its answer must not be cut: the checks below keep their answers small)."""
    answer = await query(client, sql)
    assert not answer["truncated"], sql
    return list(answer["rows"])


def _among(names: list[str]) -> str:
    """The SQL condition keeping rows of ``names`` (bag names are [A-Za-z0-9._-], nothing to escape)."""
    return "bag IN (" + ", ".join(f"'{name}'" for name in names) + ")"


async def _check_topics_and_tf(client: Client, names: list[str]) -> dict[str, dict[str, int]]:
    """Each bag's topic counts and TF edges; returns bag_info's topic counts by bag."""
    counted = {}
    for name in names:
        info = await call(client, "bag_info", bag=name)
        counted[name] = {t["name"]: t["count"] for t in info["topics"]}
        counts = await _rows(client, f"SELECT topic, count FROM topics WHERE bag = '{name}'")
        assert dict(map(tuple, counts)) == counted[name], name
        if any(t["type"] in TF_TYPES for t in info["topics"]):
            tree = await long(client, "get_tf_tree", bag=name)
            edges = await _rows(client, f"SELECT parent, child, static, count FROM tf_edges WHERE bag = '{name}'")
            wanted = {(e["parent"], e["child"], e["static"]): e["count"] for e in tree["edges"]}
            assert {(p, c, s): n for p, c, s, n in edges} == wanted, name
    return counted


async def _check_logs(client: Client, among: str) -> dict[str, int]:
    """ERROR-or-worse records of every bag with log records; returns analyze_logs' counts by bag."""
    errors = await _rows(client, f"SELECT bag, count(*) FROM logs WHERE level_rank >= 3 AND {among} GROUP BY bag")
    logged = await _rows(client, f"SELECT DISTINCT bag FROM topics WHERE count > 0 AND type IN {LOG_TYPES} AND {among}")
    assert len(logged) >= 3
    totals = {
        name: (await long(client, "analyze_logs", bag=name, min_level="ERROR", limit=1))["total"] for (name,) in logged
    }
    assert dict(map(tuple, errors)) == {name: total for name, total in totals.items() if total}
    return totals


async def _check_poses(client: Client, among: str) -> None:
    poses = await _rows(client, f"SELECT bag, topic, count(*), max(speed) FROM poses WHERE {among} GROUP BY ALL")
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


async def _found(client: Client, names: list[str], **conditions: object) -> dict[str, float]:
    """find_bags' matches among ``names``, each with the value of its (single) condition's evidence."""
    found = await long(client, "find_bags", **conditions)
    assert not found["truncated"], found["total"]  # else a bag of ``names`` might be left out
    return {m["bag"]: m["evidence"][0]["value"] for m in found["matches"] if m["bag"] in names}


def _has_topic(topic: str) -> bool:
    """find_bags' ``topic`` match: the same name, ignoring case and leading or trailing slashes."""
    return topic.strip("/").lower() == HAS_TOPIC.strip("/")


async def _check_found(
    client: Client, names: list[str], topics: dict[str, dict[str, int]], errors: dict[str, int]
) -> None:
    assert await _found(client, names, log_level="ERROR") == {name: n for name, n in errors.items() if n}
    wanted = {
        name: sum(n for topic, n in counts.items() if _has_topic(topic))
        for name, counts in topics.items()
        if any(map(_has_topic, counts))
    }
    assert len(wanted) >= 4
    assert await _found(client, names, topic=HAS_TOPIC) == wanted


async def check_corpus(client: Client, names: list[str]) -> None:
    """query_bags and find_bags agree with the per-bag tools on every bag of ``names`` (each ready on the
    server ``client`` talks to)."""
    among = _among(names)
    assert await _rows(client, f"SELECT count(*) FROM bags WHERE {among}") == [[len(names)]]
    topics = await _check_topics_and_tf(client, names)
    errors = await _check_logs(client, among)
    await _check_poses(client, among)
    await _check_found(client, names, topics, errors)
