"""Jobs of two services (bag-store and analysis) followed through one get_job / cancel_job pair on the
gateway, owned by the token that started them, each on its own service's queue."""

from __future__ import annotations

import time

import anyio
import pytest
from mcp import Client

from tests.checks.search_checks import finished
from tests.fixtures.mcp_client import call, call_error, http_client
from tests.integration.conftest import POSES_TF_MESSAGES
from tests.integration.stack import OTHER_TOKEN, TOKEN, Stack

pytestmark = pytest.mark.anyio


async def _job(client: Client, tool: str, **arguments: object) -> str:
    answer = await call(client, tool, **arguments)
    assert "job" in answer, f"{tool} finished within the budget; the test needs a job: {answer}"
    return str(answer["job"]["job_id"])


async def test_one_pair_of_job_tools_follows_the_jobs_of_two_services(
    stack: Stack, chatter: str, poses_tf: str
) -> None:
    async with http_client(f"{stack.url}/mcp", TOKEN) as client:
        names = [t.name for t in (await client.list_tools()).tools]
        assert names.count("get_job") == 1
        assert names.count("cancel_job") == 1
        search = await _job(client, "search_messages", bag=chatter, topic="/chatter", condition="regex", value="9999$")
        path = await _job(client, "analyze_trajectory", bag=poses_tf)
        kinds = {(await call(client, "get_job", job_id=j))["kind"] for j in (search, path)}
        assert kinds == {"bag_store.search", "analysis.trajectory"}
        found = await finished(client, {"job": {"job_id": search}}, timeout_s=120)
        assert found["total"] == 30  # "hello 9999", "hello 19999", ... among 300,000
        trajectory = await finished(client, {"job": {"job_id": path}}, timeout_s=120)
        assert trajectory["topic"] == "/pose_tf"
        assert trajectory["distance_2d_m"] == pytest.approx((POSES_TF_MESSAGES - 1) / 1000)


async def test_another_token_can_neither_see_nor_cancel_a_job_of_another_service(stack: Stack, poses_tf: str) -> None:
    async with http_client(f"{stack.url}/mcp", TOKEN) as owner, http_client(f"{stack.url}/mcp", OTHER_TOKEN) as other:
        job_id = await _job(owner, "analyze_trajectory", bag=poses_tf)
        assert "no job" in await call_error(other, "get_job", job_id=job_id)
        assert "no job" in await call_error(other, "cancel_job", job_id=job_id)
        assert (await call(owner, "get_job", job_id=job_id))["job_id"] == job_id
        await finished(owner, {"job": {"job_id": job_id}}, timeout_s=120)


async def test_a_job_waits_for_a_worker_of_its_own_service_and_no_other_takes_it(stack: Stack, poses_tf: str) -> None:
    stack.kill_worker(stack.latest_worker("analysis"))
    async with http_client(f"{stack.url}/mcp", TOKEN) as client:
        job_id = await _job(client, "analyze_trajectory", bag=poses_tf)
        deadline = time.monotonic() + 4  # the bag-store and plotting workers are idle all this time
        while time.monotonic() < deadline:
            assert (await call(client, "get_job", job_id=job_id))["state"] == "queued"
            await anyio.sleep(0.5)
        stack.start_worker("analysis")
        trajectory = await finished(client, {"job": {"job_id": job_id}}, timeout_s=120)
        assert trajectory["samples"] == POSES_TF_MESSAGES
