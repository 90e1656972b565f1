"""find_bags' conditions one by one (has topic, has type, recorded between, log from a node, log containing
text, topic gap longer than) over a fleet of unlike bags, each checked against what the per-bag tools say of
every bag (bag_info, analyze_logs, topic_statistics), so each condition both keeps and leaves out bags."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from mcp import Client

from bagmcp_shared.index import RECORD_TYPES
from bench.fleet_bags import fleet_bags
from tests.checks.fleet_checks import long
from tests.fixtures.bagfactory import BagKind
from tests.fixtures.inprocess import InProcess, copy_bags, in_process
from tests.fixtures.mcp_client import JsonObject, call
from tests.fixtures.small_bags import write_late_topic_bag

pytestmark = pytest.mark.anyio
SHORT = ("fleet-0000", "fleet-0001")  # the benchmark's 10 s drives: ROS 1 with an ERROR, ROS 2 an hour later
NAMES = ["drive", "drive_mcap", *SHORT, "late_imu"]
HOUR_S = 3600.0


@pytest.fixture(scope="module")
def mixed(drive_bags: dict[BagKind, Path], tmp_path_factory: pytest.TempPathFactory) -> Iterator[InProcess]:
    made = tmp_path_factory.mktemp("unlike")
    short, _ = fleet_bags(made, len(SHORT))
    paths = [drive_bags["ros1"], drive_bags["ros2-mcap"], *sorted(short.iterdir()), write_late_topic_bag(made)]
    folder = copy_bags(paths, tmp_path_factory.mktemp("mixed") / "bags")
    with in_process(folder, tmp_path_factory.mktemp("data")) as services:
        yield services


async def _found(client: Client, **conditions: object) -> dict[str, dict[str, Any]]:
    """find_bags' matches: bag -> its evidence by condition."""
    answer = await long(client, "find_bags", **conditions)
    assert answer["bags_queried"] == len(NAMES)
    assert answer["total"] == len(answer["matches"])
    return {m["bag"]: {e["condition"]: e for e in m["evidence"]} for m in answer["matches"]}


async def _infos(client: Client) -> dict[str, JsonObject]:
    return {name: await call(client, "bag_info", bag=name) for name in NAMES}


def _kept_and_left(found: dict[str, Any], truth: dict[str, bool]) -> None:
    assert set(found) == {name for name, yes in truth.items() if yes}
    assert any(truth.values())
    assert not all(truth.values())  # at least one bag must be left out


async def test_has_topic(mixed: InProcess) -> None:
    async with Client(mixed.gateway(), cache=None) as client:
        infos = await _infos(client)
        found = await _found(client, topic="rosout_agg")  # slashes and case do not matter
    topics = {name: {t["name"]: t for t in info["topics"]} for name, info in infos.items()}
    _kept_and_left(found, {name: "/rosout_agg" in t for name, t in topics.items()})
    assert found["drive"]["topic"]["value"] == topics["drive"]["/rosout_agg"]["count"]


async def test_has_type(mixed: InProcess) -> None:
    async with Client(mixed.gateway(), cache=None) as client:
        infos = await _infos(client)
        found = await _found(client, type="rcl_interfaces/Log")  # the short form of rcl_interfaces/msg/Log
    log = "rcl_interfaces/msg/Log"
    counts = {name: sum(t["count"] for t in info["topics"] if t["type"] == log) for name, info in infos.items()}
    _kept_and_left(found, {name: count > 0 for name, count in counts.items()})
    assert {name: e["type"]["value"] for name, e in found.items()} == {n: c for n, c in counts.items() if c}


async def test_recorded_between(mixed: InProcess) -> None:
    async with Client(mixed.gateway(), cache=None) as client:
        infos = await _infos(client)
        starts = {name: info["start"]["stamp_s"] for name, info in infos.items()}
        low = min(starts.values()) + HOUR_S / 2
        found = await _found(client, between=["2023-11-14T22:43:20Z", low + 5 * HOUR_S])  # ISO and epoch s
    assert low == 1_700_001_800.0  # the ISO bound above
    _kept_and_left(found, {name: low <= start <= low + 5 * HOUR_S for name, start in starts.items()})
    assert set(found) == {"fleet-0001"}
    for name, evidence in found.items():
        assert evidence["recorded"]["value"] == pytest.approx(infos[name]["duration_s"])


LogTruth = dict[str, tuple[int, float | None]]


async def _log_truth(client: Client, infos: dict[str, JsonObject], **filters: str) -> LogTruth:
    """Per bag: analyze_logs' records matching ``filters`` on every log topic (each topic on its own, so a
    record repeated on /rosout_agg counts twice, as in the logs view), and the first one's offset."""
    truth = {}
    for name, info in infos.items():
        total, first = 0, None
        for topic in (t["name"] for t in info["topics"] if t["type"] in RECORD_TYPES):
            logs = await long(client, "analyze_logs", bag=name, topic=topic, limit=500, **filters)
            total += logs["total"]
            times = [e["time"]["offset_s"] for e in logs["entries"]]
            first = min([*times, *([first] if first is not None else [])], default=None)
        truth[name] = (total, first)
    return truth


async def test_log_from_a_node(mixed: InProcess) -> None:
    async with Client(mixed.gateway(), cache=None) as client:
        infos = await _infos(client)
        truth = await _log_truth(client, infos, node="lidar")
        found = await _found(client, log_node="LIDAR")  # part of the name, any case
        both = await _found(client, log_node="planner", type="rosgraph_msgs/Log")  # AND: the ROS 1 bags
    _kept_and_left(found, {name: total > 0 for name, (total, _) in truth.items()})
    for name, evidence in found.items():
        assert (evidence["log"]["value"], evidence["log"]["offset_s"]) == pytest.approx(truth[name])
        assert "/lidar_driver" in evidence["log"]["detail"]
    assert set(both) == {"drive", "fleet-0000"}
    assert all(set(evidence) == {"type", "log"} for evidence in both.values())


async def test_log_containing_text(mixed: InProcess) -> None:
    async with Client(mixed.gateway(), cache=None) as client:
        infos = await _infos(client)
        truth = await _log_truth(client, infos, contains="failed to FIND a path")
        found = await _found(client, log_text="failed to FIND a path")
    _kept_and_left(found, {name: total > 0 for name, (total, _) in truth.items()})
    assert set(found) == {"fleet-0000"}  # every fifth short drive logs this ERROR
    assert (found["fleet-0000"]["log"]["value"], found["fleet-0000"]["log"]["offset_s"]) == pytest.approx(
        truth["fleet-0000"]
    )


async def test_topic_gap_longer_than(mixed: InProcess) -> None:
    above = 1.5
    async with Client(mixed.gateway(), cache=None) as client:
        infos = await _infos(client)
        gaps = {
            name: {
                t["name"]: (await long(client, "topic_statistics", bag=name, topic=t["name"]))["max_period_s"]
                for t in info["topics"]
                if t["count"] > 1
            }
            for name, info in infos.items()
        }
        found = await _found(client, gap_above=above)
        imu = await _found(client, gap_above=above, topic="/imu")  # the gaps of that topic only
    longest = {name: max(g.values()) for name, g in gaps.items()}
    _kept_and_left(found, {name: gap > above for name, gap in longest.items()})
    for name, evidence in found.items():
        assert evidence["gap_above"]["value"] == pytest.approx(longest[name])
        assert gaps[name][evidence["gap_above"]["detail"].split(" ")[0]] == pytest.approx(longest[name])
    assert set(imu) == {"drive", "drive_mcap"}
    for evidence in imu.values():
        assert evidence["gap_above"]["value"] == pytest.approx(2.0)  # the drive's IMU drop-out, 20 s to 22 s
        assert evidence["gap_above"]["offset_s"] == pytest.approx(20.0)
