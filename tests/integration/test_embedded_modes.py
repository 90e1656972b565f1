"""`bagmcp serve` (HTTP) and `bagmcp stdio` over a folder answer like the distributed stack."""

from __future__ import annotations

import shutil
from collections.abc import Iterator
from pathlib import Path

import anyio
import httpx
import pytest
from mcp import Client, StdioServerParameters

from tests.checks.first_tools import check_first_tools
from tests.fixtures import scenario as sc
from tests.fixtures.bagfactory import BagKind
from tests.fixtures.mcp_client import call, http_client, ingested_bags
from tests.fixtures.processes import BIN, http_ok, service
from tests.fixtures.servers import free_port

pytestmark = pytest.mark.anyio
NAMES = ["scenario", "scenario_db3", "scenario_mcap"]


@pytest.fixture(scope="module")
def bag_folder(scenario_bags: dict[BagKind, Path], tmp_path_factory: pytest.TempPathFactory) -> Path:
    folder = tmp_path_factory.mktemp("served")
    for path in scenario_bags.values():
        (shutil.copytree if path.is_dir() else shutil.copy)(path, folder / path.name)
    (folder / "notes.txt").write_text("not a bag")
    (folder / "empty.bag").write_bytes(b"")
    (folder / "fake.mcap").write_text("just text pretending to be a recording")
    (folder / "flight.ulg").write_bytes(b"ULog\x01\x12\x35\x01" + bytes(64))  # a PX4 log header
    return folder


def _serve(folder: Path, port: int, data: Path) -> list[str]:
    return [str(BIN / "bagmcp"), "serve", "--bags", str(folder), "--port", str(port), "--data", str(data)]


@pytest.fixture(scope="module")
def served(bag_folder: Path, tmp_path_factory: pytest.TempPathFactory) -> Iterator[str]:
    port = free_port()
    url = f"http://127.0.0.1:{port}"
    command = _serve(bag_folder, port, tmp_path_factory.mktemp("data"))
    with service(
        "bagmcp-serve",
        command,
        env={},
        log_dir=tmp_path_factory.mktemp("logs"),
        ready=http_ok(f"{url}/healthz"),
    ):
        yield url


async def test_serve_over_http_answers_the_first_tools_for_three_formats(served: str) -> None:
    async with http_client(f"{served}/mcp", token=None) as client:
        await ingested_bags(client, count=len(NAMES), timeout_s=60)
        await check_first_tools(client, NAMES)


async def test_stdio_answers_the_first_tools_for_three_formats(bag_folder: Path, tmp_path: Path) -> None:
    params = StdioServerParameters(
        command=str(BIN / "bagmcp"), args=["stdio", "--bags", str(bag_folder), "--data", str(tmp_path)]
    )
    async with Client(params, cache=None) as client:
        await ingested_bags(client, count=len(NAMES), timeout_s=60)
        await check_first_tools(client, NAMES)


def test_serve_lists_bags_over_rest_and_refuses_uploads_to_a_read_only_folder(served: str) -> None:
    listing = httpx.get(f"{served}/api/v1/bags").json()
    status = {b["name"]: (b["status"], b["error"]) for b in listing["bags"]}
    assert sorted(n for n, (s, _) in status.items() if s == "ready") == NAMES
    assert status["empty"] == ("failed", "empty.bag: the file is empty (0 bytes)")
    assert status["fake"][0] == "failed"
    assert "not a ROS bag" in status["fake"][1]
    assert "notes" not in status
    assert status["flight"][0] == "failed"
    assert "ULog file holds no message formats" in status["flight"][1]
    refused = httpx.post(f"{served}/api/v1/bags", params={"filename": "x.bag"}, content=b"#ROSBAG V2.0\n")
    assert refused.status_code == 405
    assert refused.json()["error"]["code"] == "read_only"


def test_serve_with_a_token_rejects_calls_without_it(bag_folder: Path, tmp_path: Path) -> None:
    port = free_port()
    command = [*_serve(bag_folder, port, tmp_path / "data"), "--token", "t0k"]
    with service(
        "bagmcp-serve-token",
        command,
        env={},
        log_dir=tmp_path,
        ready=http_ok(f"http://127.0.0.1:{port}/healthz"),
    ):
        anonymous = httpx.post(f"http://127.0.0.1:{port}/mcp", json={"jsonrpc": "2.0", "id": 1, "method": "tools/list"})
        assert anonymous.status_code == 401
        assert "resource_metadata" in anonymous.headers["www-authenticate"]
        assert anonymous.json()["error"]["code"] == "unauthorized"  # the one error shape, 401 included
        rest = httpx.get(f"http://127.0.0.1:{port}/api/v1/bags")
        assert rest.status_code == 401
        assert rest.json()["error"]["code"] == "unauthorized"
        assert rest.headers["www-authenticate"].startswith("Bearer")
        authorized = httpx.get(f"http://127.0.0.1:{port}/api/v1/bags", headers={"Authorization": "Bearer t0k"})
        assert authorized.status_code == 200


async def test_serve_answers_at_once_and_hashes_a_large_folder_in_the_background(
    scenario_bags: dict[BagKind, Path], tmp_path: Path
) -> None:
    folder = tmp_path / "bags"
    folder.mkdir()
    huge = folder / "a_huge.bag"  # first by name; small bags are still ingested first
    with huge.open("wb") as file:  # a sparse 3 GiB file that starts like a ROS 1 bag: hashing it takes seconds
        file.write(b"#ROSBAG V2.0\n")
        file.truncate(3 << 30)
    shutil.copy(scenario_bags["ros1"], folder / "scenario.bag")
    port = free_port()
    url = f"http://127.0.0.1:{port}"
    with service(
        "serve-huge", _serve(folder, port, tmp_path / "data"), env={}, log_dir=tmp_path, ready=http_ok(f"{url}/healthz")
    ):
        listed = httpx.get(f"{url}/api/v1/bags/a_huge").json()
        assert listed["status"] == "ingesting"
        assert listed["sha256"] == ""  # listed before its content was hashed
        async with http_client(f"{url}/mcp", None) as client:
            progress: list[float] = []
            with anyio.fail_after(120):
                while (bags := {b["name"]: b for b in (await call(client, "list_bags"))["bags"]})["scenario"][
                    "status"
                ] != "ready":
                    await anyio.sleep(0.05)
                info = await call(client, "bag_info", bag="scenario")  # usable while the large bag is hashed
                assert info["message_count"] == sum(sc.COUNTS.values())
                while (huge_bag := bags["a_huge"])["status"] == "ingesting":
                    progress.append(huge_bag["progress"] or 0.0)
                    await anyio.sleep(0.1)
                    bags = {b["name"]: b for b in (await call(client, "list_bags"))["bags"]}
        assert any(0 < p < 0.5 for p in progress), progress  # hashing is the first half of its progress
        assert progress == sorted(progress)
        done = httpx.get(f"{url}/api/v1/bags/a_huge").json()
        assert done["status"] == "failed"
        assert len(done["sha256"]) == 64  # hashed in the background, then refused with the reason
        assert done["error"]
