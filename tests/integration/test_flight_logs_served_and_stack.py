"""Every tool on a PX4 ULog, an ArduPilot DataFlash log, JSON and protobuf MCAP in both ways of running:
`bagmcp serve` over a folder (with a firmware .bin it must not list) and the distributed stack (uploads,
ingest and long work in Celery workers)."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import anyio
import pytest

from tests.checks.flight_checks import check_flight_logs
from tests.fixtures.flight_files import NAMES, write_firmware, write_flight_files
from tests.fixtures.mcp_client import call, http_client
from tests.fixtures.processes import BIN, http_ok, service
from tests.fixtures.servers import free_port
from tests.integration.stack import TOKEN, Stack

pytestmark = pytest.mark.anyio


@pytest.fixture(scope="module")
def flight_files(tmp_path_factory: pytest.TempPathFactory) -> list[Path]:
    return write_flight_files(tmp_path_factory.mktemp("flights"))


@pytest.fixture(scope="module")
def served(flight_files: list[Path], tmp_path_factory: pytest.TempPathFactory) -> Iterator[str]:
    folder = flight_files[0].parent
    write_firmware(folder)
    port = free_port()
    command = [str(BIN / "bagmcp"), "serve", "--bags", str(folder), "--port", str(port)]
    env = {"BAGMCP_DATA_DIR": str(tmp_path_factory.mktemp("data"))}
    url = f"http://127.0.0.1:{port}"
    with service(
        "serve-flights", command, env=env, log_dir=tmp_path_factory.mktemp("logs"), ready=http_ok(f"{url}/healthz")
    ):
        yield url


async def test_every_tool_answers_on_flight_logs_through_the_embedded_server(served: str) -> None:
    async with http_client(f"{served}/mcp", None) as client:
        with anyio.fail_after(120):
            while any(b["status"] == "ingesting" for b in (await call(client, "list_bags"))["bags"]):
                await anyio.sleep(0.2)
        listed = {b["name"] for b in (await call(client, "list_bags"))["bags"]}
        assert listed == set(NAMES)  # the firmware .bin is no recording
        await check_flight_logs(client)


async def test_every_tool_answers_on_uploaded_flight_logs_through_the_stack(
    stack: Stack, flight_files: list[Path]
) -> None:
    names = [str(stack.upload_ok(path)["name"]) for path in flight_files]
    assert names == list(NAMES)
    await stack.wait_ready(names)
    async with http_client(f"{stack.url}/mcp", TOKEN) as client:
        await check_flight_logs(client)
