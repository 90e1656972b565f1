"""The analysis and plotting tools through the gateway in both ways of running: `bagmcp serve` over a folder
and the distributed stack (uploaded bags, Celery workers on their own queues), plus plot artifacts over REST."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import anyio
import httpx
import pytest

from tests.checks.analysis_checks import check_analysis
from tests.checks.plot_checks import check_plots, plot
from tests.fixtures.bagfactory import BagKind
from tests.fixtures.drive_bags import write_drive_bags
from tests.fixtures.inprocess import copy_bags
from tests.fixtures.mcp_client import call, http_client
from tests.fixtures.processes import BIN, http_ok, service
from tests.fixtures.servers import free_port
from tests.integration.stack import TOKEN, Stack

pytestmark = pytest.mark.anyio
NAMES = ["drive", "drive_db3", "drive_mcap"]


@pytest.fixture(scope="module")
def drive_bags(tmp_path_factory: pytest.TempPathFactory) -> dict[BagKind, Path]:
    return write_drive_bags(tmp_path_factory.mktemp("drive"))


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
        with anyio.fail_after(120):
            while any(b["status"] == "ingesting" for b in (await call(client, "list_bags"))["bags"]):
                await anyio.sleep(0.2)


async def test_analysis_answers_on_three_formats_through_the_embedded_server(served: str) -> None:
    await _ready(served)
    async with http_client(f"{served}/mcp", None) as client:
        await check_analysis(client, NAMES)


async def test_plots_render_on_three_formats_through_the_embedded_server(served: str) -> None:
    await _ready(served)
    async with http_client(f"{served}/mcp", None) as client:
        for bag in NAMES:
            await check_plots(client, bag, next(n for n in NAMES if n != bag))


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
