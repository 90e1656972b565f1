"""Answers across bags (query_bags, find_bags) checked against the per-bag tools' own answers on the same
bags, through any MCP client: in process, ``bagmcp serve`` or the stack."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from mcp import Client

from tests.checks.search_checks import finished
from tests.fixtures.mcp_client import JsonObject, call, call_error

ODOM = "/odom"


@dataclass(frozen=True)
class PerBag:
    """What the per-bag tools say about one bag."""

    max_speed_mps: float
    errors: int  # ERROR or FATAL records on /rosout
    first_error_s: float | None
    closest_m: float  # closest approach of /odom to the probe point
    first_within_s: float | None  # first scan closer than the probe range


async def long(client: Client, tool: str, **arguments: object) -> JsonObject:
    return await finished(client, await call(client, tool, **arguments))


async def per_bag(client: Client, bag: str, *, point: tuple[float, float], within_m: float) -> PerBag:
    trajectory = await long(client, "analyze_trajectory", bag=bag, topic=ODOM)
    logs = await long(client, "analyze_logs", bag=bag, min_level="ERROR", topic="/rosout")
    near = await long(
        client,
        "search_messages",
        bag=bag,
        topic=ODOM,
        condition="near_position",
        value={"x": point[0], "y": point[1], "radius": 1000.0},
    )
    lidar = await long(client, "analyze_lidar_scan", bag=bag, topic="/scan", within=within_m)
    first_error = logs["summary"]["first_error"] if logs["summary"] else None
    first_within = lidar["first_within"]
    return PerBag(
        max_speed_mps=trajectory["max_speed_mps"],
        errors=logs["total"],
        first_error_s=first_error["time"]["offset_s"] if first_error else None,
        closest_m=near["closest"]["distance_m"],
        first_within_s=first_within["time"]["offset_s"] if first_within else None,
    )


async def query(client: Client, sql: str) -> JsonObject:
    return await long(client, "query_bags", sql=sql)


def by_bag(answer: JsonObject) -> dict[str, list[Any]]:
    columns = answer["columns"]
    return {row[columns.index("bag")]: row for row in answer["rows"]}


async def check_fleet(client: Client, names: list[str], *, point: tuple[float, float] = (2.0, 0.3)) -> None:
    """query_bags and find_bags agree with analyze_trajectory, analyze_logs, search_messages and
    analyze_lidar_scan on every bag of ``names``."""
    within_m = 0.5
    truth = {name: await per_bag(client, name, point=point, within_m=within_m) for name in names}
    wanted = ", ".join(f"'{n}'" for n in names)
    odom = f"topic = '{ODOM}' AND bag IN ({wanted})"

    speeds = by_bag(await query(client, f"SELECT bag, max(speed) FROM poses WHERE {odom} GROUP BY bag"))
    for name, facts in truth.items():
        assert math.isclose(speeds[name][1], facts.max_speed_mps, rel_tol=0.03), (name, speeds[name], facts)

    errors = by_bag(
        await query(
            client,
            f"SELECT bag, count(*), min(offset_s) FROM logs WHERE topic = '/rosout' AND level_rank >= 3 "
            f"AND bag IN ({wanted}) GROUP BY bag",
        )
    )
    for name, facts in truth.items():
        assert errors[name][1] == facts.errors, (name, errors[name], facts)
        assert facts.first_error_s is not None
        assert math.isclose(errors[name][2], facts.first_error_s, abs_tol=1e-3)

    closest = by_bag(
        await query(
            client,
            f"SELECT bag, min(sqrt((x - {point[0]})^2 + (y - {point[1]})^2)) FROM poses WHERE {odom} GROUP BY bag",
        )
    )
    for name, facts in truth.items():
        assert math.isclose(closest[name][1], facts.closest_m, abs_tol=1e-6), (name, closest[name], facts)

    found = await long(
        client,
        "find_bags",
        log_level="ERROR",
        near=[point[0], point[1], 0.5],
        scan_below=within_m,
        speed_above=0.1,
    )
    matched = {m["bag"]: {e["condition"]: e for e in m["evidence"]} for m in found["matches"]}
    for name, facts in truth.items():
        evidence = matched[name]
        assert math.isclose(evidence["near"]["value"], facts.closest_m, abs_tol=1e-6)
        assert math.isclose(evidence["speed_above"]["value"], facts.max_speed_mps, rel_tol=0.03)
        assert facts.first_within_s is not None
        assert math.isclose(evidence["scan_below"]["offset_s"], facts.first_within_s, abs_tol=1e-3)
        assert evidence["log"]["value"] >= facts.errors  # every log topic (ROS 1 also has /rosout_agg)


async def check_refusals(client: Client) -> None:
    """Wrong tables and columns name the right ones; writes and second statements are refused."""
    wrong_table = await call_error(client, "query_bags", sql="SELECT * FROM odometry")
    assert "poses(" in wrong_table
    assert "logs(" in wrong_table
    wrong_column = await call_error(client, "query_bags", sql="SELECT velocity FROM poses")
    assert "velocity" in wrong_column
    assert "speed" in wrong_column
    assert "only SELECT" in await call_error(client, "query_bags", sql="DELETE FROM poses")
    assert "exactly one" in await call_error(client, "query_bags", sql="SELECT 1; SELECT 2")
