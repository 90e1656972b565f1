"""The analysis and plotting tools through the gateway in both ways of running: `bagmcp serve` over a folder
and the distributed stack (uploaded bags, Celery workers on their own queues), plus plot artifacts over REST,
progress of a long analysis, and a plot job that only a plotting worker runs."""

from __future__ import annotations

import base64
import time
from collections.abc import Iterator
from pathlib import Path

import anyio
import httpx
import pytest

from tests.checks.analysis_checks import check_analysis
from tests.checks.paper_tasks import check_paper_tasks
from tests.checks.plot_checks import check_plots, plot
from tests.checks.search_checks import finished
from tests.fixtures.bagfactory import BagKind
from tests.fixtures.inprocess import copy_bags
from tests.fixtures.mcp_client import call, http_client, ingested_bags, text_of
from tests.fixtures.processes import BIN, http_ok, service
from tests.fixtures.servers import free_port
from tests.integration.conftest import POSES_TF_MESSAGES
from tests.integration.stack import TOKEN, Stack, new_token

pytestmark = pytest.mark.anyio
NAMES = ["drive", "drive_db3", "drive_mcap"]


@pytest.fixture(scope="module")
def served(drive_bags: dict[BagKind, Path], tmp_path_factory: pytest.TempPathFactory) -> Iterator[str]:
    folder = copy_bags(list(drive_bags.values()), tmp_path_factory.mktemp("served-drive") / "bags")
    port = free_port()
    command = [str(BIN / "bagmcp"), "serve", "--bags", str(folder), "--port", str(port)]
    env = {"BAGMCP_DATA_DIR": str(tmp_path_factory.mktemp("data"))}
    url = f"http://127.0.0.1:{port}"
    with service(
        "serve-drive", command, env=env, log_dir=tmp_path_factory.mktemp("logs"), ready=http_ok(f"{url}/healthz")
    ):
        yield url


@pytest.fixture(scope="module")
def stack_drive(stack: Stack, drive_bags: dict[BagKind, Path]) -> list[str]:
    names = [str(stack.upload_ok(path)["name"]) for path in drive_bags.values()]
    anyio.run(stack.wait_ready, names)
    return names


async def _ready(url: str) -> None:
    async with http_client(f"{url}/mcp", None) as client:
        await ingested_bags(client)


async def test_analysis_answers_on_three_formats_through_the_embedded_server(served: str) -> None:
    await _ready(served)
    async with http_client(f"{served}/mcp", None) as client:
        await check_analysis(client, NAMES)


async def test_plots_render_on_three_formats_through_the_embedded_server(served: str) -> None:
    await _ready(served)
    async with http_client(f"{served}/mcp", None) as client:
        for bag in NAMES:
            await check_plots(client, bag, next(n for n in NAMES if n != bag))


async def test_the_papers_ten_tasks_take_two_calls_each_through_the_embedded_server(served: str) -> None:
    await _ready(served)
    async with http_client(f"{served}/mcp", None) as client:
        for bag in NAMES:
            await check_paper_tasks(client, bag, NAMES)


async def test_the_papers_ten_tasks_take_two_calls_each_through_the_stack(stack: Stack, stack_drive: list[str]) -> None:
    async with http_client(f"{stack.url}/mcp", TOKEN) as client:
        await check_paper_tasks(client, stack_drive[-1], stack_drive, settle=stack.job_ended)


async def test_the_core_profile_answers_the_papers_ten_tasks(stack: Stack, stack_drive: list[str]) -> None:
    """A small model's token (profile core, the scopes filter_bag needs) does every task, in two calls each."""
    small = new_token(stack, "core-model", "--profile", "core", "--scopes", "read,upload")
    async with http_client(f"{stack.url}/mcp", small) as client:
        listed = {t.name for t in (await client.list_tools()).tools}
        assert "describe_topic" not in listed  # still the small profile
        await check_paper_tasks(client, stack_drive[0], stack_drive, settle=stack.job_ended)


async def test_analysis_answers_on_three_formats_through_the_stack(stack: Stack, stack_drive: list[str]) -> None:
    async with http_client(f"{stack.url}/mcp", TOKEN) as client:
        await check_analysis(client, stack_drive)


async def test_plots_render_through_the_stack_and_download_over_rest_only_with_a_token(
    stack: Stack, stack_drive: list[str]
) -> None:
    async with http_client(f"{stack.url}/mcp", TOKEN) as client:
        for bag in stack_drive:
            await check_plots(client, bag, next(n for n in stack_drive if n != bag))
        report, _ = await plot(client, "plot_2d", bag=stack_drive[0])
    url = report["artifact"]["url"]
    assert url == f"{stack.url}/api/v1/artifacts/{report['artifact']['id']}"
    refused = httpx.get(url)
    assert refused.status_code == 401
    assert refused.json()["error"]["code"] == "unauthorized"
    fetched = httpx.get(url, headers={"Authorization": f"Bearer {TOKEN}"})
    assert fetched.status_code == 200
    assert fetched.headers["content-type"] == "image/png"
    assert len(fetched.content) == report["artifact"]["bytes"]
    missing = httpx.get(f"{stack.url}/api/v1/artifacts/0000", headers={"Authorization": f"Bearer {TOKEN}"})
    assert missing.status_code == 404


async def test_a_long_trajectory_reports_progress_while_the_analysis_worker_decodes(
    stack: Stack, poses_tf: str
) -> None:
    notified: list[float] = []

    async def on_progress(progress: float, total: float | None, message: str | None) -> None:
        notified.append(progress)

    async with http_client(f"{stack.url}/mcp", TOKEN) as client:
        answer = await client.call_tool("analyze_trajectory", {"bag": poses_tf}, progress_callback=on_progress)
        started = answer.structured_content
        assert started is not None
        assert "result" not in started, "the trajectory finished within the budget; the test needs a job"
        assert started["job"]["kind"] == "analysis.trajectory"
        assert notified, "no progress notification reached the client"
        seen: list[tuple[float, str]] = []
        with anyio.fail_after(120):
            while (job := await call(client, "get_job", job_id=started["job"]["job_id"]))["state"] != "succeeded":
                assert job["state"] in ("queued", "running"), job
                seen.append((job["progress"], job["message"]))
                await anyio.sleep(0.1)
    assert job["result"]["samples"] == POSES_TF_MESSAGES
    progress = [p for p, _ in seen]
    assert progress == sorted(progress)
    assert any(0.05 < p < 0.99 for p in progress), seen  # part way, in step with the messages decoded
    assert any(m.endswith(f"of {POSES_TF_MESSAGES} messages of /pose_tf") for _, m in seen), seen


async def test_a_plot_job_waits_for_a_plotting_worker_and_the_same_call_then_shows_the_image(
    stack: Stack, poses_tf: str
) -> None:
    stack.kill_worker(stack.latest_worker("plotting"))
    restarted = False
    try:
        async with http_client(f"{stack.url}/mcp", TOKEN) as client:
            answer = await client.call_tool("plot_2d", {"bag": poses_tf})
            assert answer.structured_content is not None
            job = answer.structured_content["job"]
            assert job["kind"] == "plotting.xy"
            assert "call plot_2d again with the same arguments" in text_of(answer)
            deadline = time.monotonic() + 4  # the bag-store and analysis workers are idle all this time
            while time.monotonic() < deadline:
                assert (await call(client, "get_job", job_id=job["job_id"]))["state"] == "queued"
                await anyio.sleep(0.5)
            stack.start_worker("plotting")
            restarted = True
            report = await finished(client, {"job": job}, timeout_s=120)
            assert [s["points"] for s in report["series"]] == [POSES_TF_MESSAGES, POSES_TF_MESSAGES]
            again = await client.call_tool("plot_2d", {"bag": poses_tf})
    finally:
        if not restarted:
            stack.start_worker("plotting")
    assert again.structured_content is not None
    assert again.structured_content["result"]["artifact"]["id"] == report["artifact"]["id"]
    inline = base64.b64decode(next(c for c in again.content if c.type == "image").data)
    fetched = httpx.get(report["artifact"]["url"], headers={"Authorization": f"Bearer {TOKEN}"})
    assert fetched.content == inline
