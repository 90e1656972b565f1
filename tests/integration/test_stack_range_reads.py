"""The stack reads bare MCAP files, ROS 1 bags and ROS 2 directories of MCAP or sqlite3 files where they are
stored: its answers equal the embedded server's on the same files, the service that answered holds blocks of
them, and neither it nor the worker that ingested them holds a whole copy."""

from __future__ import annotations

from pathlib import Path

import httpx
import pytest
from mcp.client.client import Client

from tests.checks.search_checks import finished
from tests.fixtures.bagfactory import BagKind
from tests.fixtures.inprocess import copy_bags, in_process
from tests.fixtures.mcp_client import JsonObject, call, http_client
from tests.integration.stack import TOKEN, Stack, service_counters
from tests.integration.test_range_reads import write_padded_db3, write_padded_mcap, write_padded_ros1

pytestmark = pytest.mark.anyio

TIMES = [0.0, 7.77, 12.345, 29.99]


async def answers(client: Client, names: list[str]) -> list[JsonObject]:
    found: list[JsonObject] = []
    for name in names:
        found.append(await call(client, "describe_topic", bag=name, topic="/pose"))
        for at in TIMES:
            found.append(await call(client, "get_message_at_time", bag=name, topic="/pose", time=at))
        found.append(await call(client, "get_messages_in_range", bag=name, topic="/status", start=3.0, end=4.5))
    return found


async def ros2_answers(client: Client, name: str) -> list[JsonObject]:
    """A ROS 2 directory of one MCAP file with metadata.yaml (/topic: ten strings over 4.5 s)."""
    found = [await call(client, "describe_topic", bag=name, topic="/topic")]
    for at in (0.0, 2.0, 4.5):
        found.append(await call(client, "get_message_at_time", bag=name, topic="/topic", time=at))
    found.append(await call(client, "get_messages_in_range", bag=name, topic="/rosout", start=0.0, end=4.5))
    return found


async def scenario_answers(client: Client, name: str) -> list[JsonObject]:
    """The scenario bag (a robot on a circle for 10 s): odometry at instants, commands in a window, the
    trajectory analysis (which decodes every /odom message where the columnar index does not answer)."""
    found = [await call(client, "describe_topic", bag=name, topic="/odom")]
    for at in (0.0, 2.5, 7.0, 9.9):
        found.append(await call(client, "get_message_at_time", bag=name, topic="/odom", time=at))
    found.append(await call(client, "get_messages_in_range", bag=name, topic="/cmd_vel", start=3.0, end=4.5))
    found.append(await finished(client, await call(client, "analyze_trajectory", bag=name), timeout_s=120))
    return found


def caches_of(stack: Stack) -> list[Path]:
    """The bag-store service's cache and every worker's."""
    caches = [stack.bag_store_data / "cache"]
    return caches + [stack.logs.parent / f"{of}-worker-{i}" / "cache" for i, (of, _) in enumerate(stack.workers, 1)]


async def test_ros2_sqlite3_answers_by_range_equal_the_embedded_servers_and_no_process_holds_a_db3(
    stack: Stack, tmp_path: Path, scenario_bags: dict[BagKind, Path]
) -> None:
    padded = write_padded_db3(tmp_path / "ranged_db3")
    scenario = scenario_bags["ros2-sqlite3"]
    uploaded = [stack.upload_ok(path) for path in (padded, scenario)]
    names = [str(bag["name"]) for bag in uploaded]
    await stack.wait_ready(names)
    async with http_client(f"{stack.url}/mcp", TOKEN) as client:
        remote = await answers(client, names[:1]) + await scenario_answers(client, names[1])
    with in_process(copy_bags([padded, scenario], tmp_path / "served", names=names), tmp_path / "data") as services:
        async with Client(services.gateway(), cache=None) as client:
            local = await answers(client, names[:1]) + await scenario_answers(client, names[1])
    assert remote == local
    assert remote[2]["message"]["time"]["offset_s"] == pytest.approx(7.77)
    assert remote[-1]["distance_2d_m"] > 0
    caches = caches_of(stack)
    ours = {f.name for bag in (padded, scenario) for f in bag.glob("*.db3")}
    assert ours
    for cache in caches:
        for bag in uploaded:
            assert not (cache / str(bag["id"])).exists()  # no whole copy in the service or any worker
        # nor one of its storage files anywhere in a cache (other tests' bags on this stack may be copied whole)
        assert not [f for f in cache.rglob("*.db3") if f.name in ours]
    db3_bytes = max(f.stat().st_size for f in padded.glob("*.db3"))
    blocks = caches[0] / ".blocks" / "blocks"
    held = [f.stat().st_size for f in blocks.rglob("*") if f.is_file()]
    assert held  # the service read blocks of them
    assert max(held) < db3_bytes  # blocks, never the file in one piece


async def test_mcap_ros1_and_ros2_answers_by_range_equal_the_embedded_servers(
    stack: Stack, tmp_path: Path, corpus: Path
) -> None:
    bags = [write_padded_mcap(tmp_path / "ranged_mcap.mcap"), write_padded_ros1(tmp_path / "ranged_ros1.bag", "lz4")]
    ros2 = corpus / "ros2_mcap" / "rosbag2_talker"
    uploaded = [stack.upload_ok(path) for path in [*bags, ros2]]
    names = [str(bag["name"]) for bag in uploaded]
    await stack.wait_ready(names)
    async with http_client(f"{stack.url}/mcp", TOKEN) as client:
        remote = await answers(client, names[:2]) + await ros2_answers(client, names[2])
    with in_process(copy_bags([*bags, ros2], tmp_path / "served", names=names), tmp_path / "data") as services:
        async with Client(services.gateway(), cache=None) as client:
            local = await answers(client, names[:2]) + await ros2_answers(client, names[2])
    assert remote == local
    assert remote[2]["message"]["time"]["offset_s"] == pytest.approx(7.77)
    caches = caches_of(stack)
    assert any(cache.is_dir() for cache in caches[1:])  # the worker that ingested them has a cache
    for cache in caches:
        for bag in uploaded:
            assert not (cache / str(bag["id"])).exists()  # no whole copy in the service or any worker
    cache = caches[0]
    assert any((cache / ".blocks" / "blocks").iterdir())
    counters = service_counters(stack.bag_store_url)["service"]
    assert counters["bagmcp_s3_fetched_bytes_total"] > 0
    assert counters["bagmcp_block_cache_misses_total"] > 0
    assert counters["bagmcp_block_cache_hits_total"] > 0
    assert httpx.get(f"{stack.bag_store_url}/metrics").status_code == 401
