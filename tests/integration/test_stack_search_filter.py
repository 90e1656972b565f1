"""Issue 4 through the gateway of the distributed stack: search, jobs with progress and cancel,
filter_bag (counts confirmed by bag_info and `bagmcp info`), and a worker killed mid-filter."""

from __future__ import annotations

from collections.abc import AsyncIterator
from contextlib import asynccontextmanager
from pathlib import Path
from typing import Any

import anyio
import pytest
from mcp import Client

from tests.checks.search_checks import (
    check_cancel_stops_a_running_job,
    check_search,
    check_slow_search_becomes_a_job_with_progress,
    finished,
)
from tests.fixtures import scenario as sc
from tests.fixtures.bagfactory import BagKind
from tests.fixtures.mcp_client import call, call_error, http_client
from tests.integration.bag_downloads import download_info
from tests.integration.conftest import CHATTER_MESSAGES, SCENARIO_NAMES
from tests.integration.stack import OTHER_TOKEN, TOKEN, Stack

pytestmark = pytest.mark.anyio


@asynccontextmanager
async def client_of(stack: Stack) -> AsyncIterator[Client]:
    async with http_client(f"{stack.url}/mcp", TOKEN) as client:
        yield client


async def test_search_answers_on_three_formats_through_the_gateway(
    stack: Stack, uploaded: dict[BagKind, dict[str, Any]]
) -> None:
    async with client_of(stack) as client:
        await check_search(client, SCENARIO_NAMES)


async def test_a_slow_search_becomes_a_job_with_progress_relayed_by_the_gateway(stack: Stack, chatter: str) -> None:
    async with client_of(stack) as client:
        await check_slow_search_becomes_a_job_with_progress(client, chatter)


async def test_cancel_job_stops_a_running_search_in_the_worker(stack: Stack, chatter: str) -> None:
    async with client_of(stack) as client:
        await check_cancel_stops_a_running_job(client, chatter)


async def test_jobs_belong_to_the_token_that_started_them(stack: Stack, chatter: str) -> None:
    async with client_of(stack) as client:
        answer = await call(client, "search_messages", bag=chatter, topic="/chatter", condition="contains", value="x")
        job_id = answer["job"]["job_id"]
        assert (await call(client, "get_job", job_id=job_id))["job_id"] == job_id
    async with http_client(f"{stack.url}/mcp", OTHER_TOKEN) as stranger:
        assert "no job" in await call_error(stranger, "get_job", job_id=job_id)
        assert "no job" in await call_error(stranger, "cancel_job", job_id=job_id)
    async with client_of(stack) as client:
        assert (await call(client, "cancel_job", job_id=job_id))["job_id"] == job_id


async def _filter(client: Client, **arguments: object) -> dict[str, Any]:
    return await finished(client, await call(client, "filter_bag", **arguments))


@pytest.mark.parametrize(("source", "fmt"), [("scenario", None), ("scenario_db3", None), ("scenario_mcap", "ros1")])
async def test_filter_bag_keeps_exactly_the_requested_topics(
    stack: Stack, uploaded: dict[BagKind, dict[str, Any]], tmp_path: Path, source: str, fmt: str | None
) -> None:
    async with client_of(stack) as client:
        result = await _filter(
            client,
            bag=source,
            include_topics=["/cmd_vel", "odom"],
            name=f"{source}-two-topics",
            **({"format": fmt} if fmt else {}),
        )
        expected = {"/cmd_vel": sc.COUNTS["/cmd_vel"], "/odom": sc.COUNTS["/odom"]}
        assert result["counts"] == expected
        assert result["created"] is True
        info = await call(client, "bag_info", bag=result["bag_id"])
        assert {t["name"]: t["count"] for t in info["topics"]} == expected
        assert info["name"] == f"{source}-two-topics"
        assert info["format"] == (fmt or {"scenario": "ros1", "scenario_db3": "ros2-sqlite3"}.get(source, "ros2-mcap"))
    cli = download_info(stack.url, TOKEN, result["bag_id"], tmp_path)
    assert {t["name"]: t["count"] for t in cli["topics"]} == expected
    assert not (stack.bag_store_data / "cache" / str(result["bag_id"])).exists()  # streamed from S3, not copied


async def test_filter_bag_applies_a_window_and_per_topic_rates(
    stack: Stack, uploaded: dict[BagKind, dict[str, Any]]
) -> None:
    async with client_of(stack) as client:
        result = await _filter(
            client, bag="scenario_mcap", include_topics=["/odom", "/scan"], start=2.0, end=6.0, rates={"/odom": 5}
        )
        assert result["counts"] == {"/odom": 21, "/scan": 21}  # 0.2 s apart over 4 s inclusive
        first = await call(client, "get_messages_in_range", bag=result["bag_id"], topic="/odom", max_messages=3)
        offsets = [m["offset_s"] for m in first["messages"]]
        assert offsets == pytest.approx([0.0, 0.2, 0.4])
        assert first["start"]["stamp_s"] == pytest.approx(sc.START_NS / 1e9 + 2.0)  # the new bag starts at 2 s


async def test_the_same_filter_twice_gives_the_same_bag_and_names_are_never_overwritten(
    stack: Stack, uploaded: dict[BagKind, dict[str, Any]]
) -> None:
    async with client_of(stack) as client:
        request = {"bag": "scenario", "include_topics": ["/rosout"]}
        first = await _filter(client, **request)
        again = await _filter(client, **request)
        assert again["bag_id"] == first["bag_id"]
        assert again["created"] is False
        clash = await call_error(client, "filter_bag", bag="scenario", include_topics=["/tf"], name="scenario_db3")
        assert "exists already" in clash
        unknown = await call_error(client, "filter_bag", bag="scenario", include_topics=["/nope"])
        assert "/nope" in unknown
        assert "/cmd_vel" in unknown


async def test_a_worker_killed_mid_filter_leaves_no_half_bag_and_the_job_is_redelivered(
    stack: Stack, chatter: str
) -> None:
    name = "chatter-killed-copy"
    async with client_of(stack) as client:
        answer = await call(client, "filter_bag", bag=chatter, name=name)
        job_id = answer["job"]["job_id"]
        with anyio.fail_after(60):
            while (job := await call(client, "get_job", job_id=job_id))["progress"] <= 0.05:
                assert job["state"] in ("queued", "running"), job
                await anyio.sleep(0.05)
        before = stack.objects()
        stack.kill_worker(stack.latest_worker())
        listing = await call(client, "list_bags", name=name)
        assert listing["total"] == 0
        assert stack.objects() == before
        stack.start_worker()
        result = await finished(client, {"job": {"job_id": job_id}}, timeout_s=120)
        assert result["counts"] == {"/chatter": CHATTER_MESSAGES}
        listing = await call(client, "list_bags", name=name)
        assert [b["name"] for b in listing["bags"]] == [name]
        assert listing["bags"][0]["message_count"] == CHATTER_MESSAGES
