"""The distributed mode for real: redis-server, weed S3, bag-store, a Celery worker and the gateway
as separate processes; bags uploaded with `bagmcp upload`; tools called through the gateway."""

from __future__ import annotations

import tarfile
from collections.abc import Iterator
from pathlib import Path

import httpx
import pytest

from tests.checks.first_tools import check_first_tools
from tests.fixtures.archives import zip_directory
from tests.fixtures.bagfactory import BagKind
from tests.fixtures.mcp_client import http_client
from tests.fixtures.processes import wait_until
from tests.integration.conftest import SCENARIO_NAMES
from tests.integration.stack import SERVICE_TOKEN, TOKEN, Stack

pytestmark = pytest.mark.anyio
NAMES = SCENARIO_NAMES


def _names(stack: Stack) -> list[str]:
    listing = httpx.get(f"{stack.url}/api/v1/bags", params={"limit": 500}, headers=_auth()).json()
    return sorted(b["name"] for b in listing["bags"])


async def test_uploaded_bags_answer_the_first_tools_through_the_gateway(
    stack: Stack, uploaded: dict[BagKind, dict[str, object]]
) -> None:
    assert sorted(str(a["name"]) for a in uploaded.values()) == NAMES
    await stack.wait_ready(NAMES)
    async with http_client(f"{stack.url}/mcp", TOKEN) as client:
        await check_first_tools(client, NAMES)


async def test_the_ingest_index_and_bag_objects_are_in_s3(
    stack: Stack, uploaded: dict[BagKind, dict[str, object]]
) -> None:
    await stack.wait_ready(NAMES)
    objects = stack.objects()
    for answer in uploaded.values():
        assert f"indexes/{answer['id']}/summary.json" in objects
        assert any(o.startswith(f"bags/{answer['id']}/") for o in objects)


def test_uploading_the_same_bag_twice_is_deduplicated(
    stack: Stack, uploaded: dict[BagKind, dict[str, object]], scenario_bags: dict[BagKind, Path]
) -> None:
    answer = stack.upload_ok(scenario_bags["ros1"])
    assert answer["id"] == uploaded["ros1"]["id"]
    assert answer["duplicate"] is True


@pytest.mark.parametrize(
    ("label", "content", "status", "code"),
    [
        ("text.bag", b"just some text, not a bag\n" * 10, 422, "invalid_bag"),
        ("empty.bag", b"", 400, "bad_upload"),
    ],
)
def test_bad_uploads_are_refused_and_nothing_is_stored(
    stack: Stack,
    uploaded: dict[BagKind, dict[str, object]],
    label: str,
    content: bytes,
    status: int,
    code: str,
) -> None:
    before, names_before = stack.objects(), _names(stack)
    response = httpx.post(
        f"{stack.url}/api/v1/bags",
        params={"filename": label},
        content=content,
        headers={"Authorization": f"Bearer {TOKEN}"},
    )
    assert response.status_code == status
    assert response.json()["error"]["code"] == code
    assert stack.objects() == before
    assert _names(stack) == names_before


def test_a_truncated_bag_is_refused_with_the_reason(
    stack: Stack,
    uploaded: dict[BagKind, dict[str, object]],
    scenario_bags: dict[BagKind, Path],
    tmp_path: Path,
) -> None:
    whole = scenario_bags["ros1"].read_bytes()
    cut = tmp_path / "cut.bag"
    cut.write_bytes(whole[: len(whole) // 2])
    before = stack.objects()
    result = stack.upload(cut)
    assert result.returncode == 1
    assert "422" in result.stderr
    assert "cut" in result.stderr
    assert stack.objects() == before


async def test_unknown_ids_and_bad_tokens_get_clear_errors(stack: Stack) -> None:
    missing = httpx.get(f"{stack.url}/api/v1/bags/ffffffffffff", headers={"Authorization": f"Bearer {TOKEN}"})
    assert missing.status_code == 404
    assert missing.json()["error"]["code"] == "bag_not_found"
    assert httpx.get(f"{stack.url}/api/v1/bags", headers={"Authorization": "Bearer wrong"}).status_code == 401
    anonymous = httpx.post(f"{stack.url}/mcp", json={"jsonrpc": "2.0", "id": 1, "method": "tools/list"})
    assert anonymous.status_code == 401


def _auth() -> dict[str, str]:
    return {"Authorization": f"Bearer {TOKEN}"}


def test_a_zipped_ros2_directory_uploads_through_the_gateway(
    stack: Stack,
    uploaded: dict[BagKind, dict[str, object]],
    scenario_bags: dict[BagKind, Path],
    tmp_path: Path,
) -> None:
    source = scenario_bags["ros2-sqlite3"]
    archive = zip_directory(source, tmp_path / "zipped_db3.zip")
    response = httpx.post(
        f"{stack.url}/api/v1/bags",
        params={"filename": archive.name},
        headers=_auth(),
        content=archive.read_bytes(),
    )
    assert response.status_code == 200  # same content as the sqlite3 bag uploaded as tar: deduplicated
    assert response.json()["duplicate"] is True
    assert response.json()["bag"]["id"] == uploaded["ros2-sqlite3"]["id"]


def test_an_archive_with_a_path_escaping_its_folder_is_refused(stack: Stack, tmp_path: Path) -> None:
    archive = tmp_path / "evil.tar"
    payload = tmp_path / "payload"
    payload.write_bytes(b"#ROSBAG V2.0\n")
    with tarfile.open(archive, "w") as tar:
        tar.add(payload, arcname="../../escaped.bag")
    before = stack.objects()
    response = httpx.post(
        f"{stack.url}/api/v1/bags",
        params={"filename": archive.name},
        headers=_auth(),
        content=archive.read_bytes(),
    )
    assert response.status_code == 400
    assert "unsafe path" in response.json()["error"]["message"]
    assert stack.objects() == before


def test_an_interrupted_upload_leaves_nothing_behind(
    stack: Stack, uploaded: dict[BagKind, dict[str, object]], scenario_bags: dict[BagKind, Path]
) -> None:
    before, names_before = stack.objects(), _names(stack)
    data = scenario_bags["ros1"].read_bytes()

    def cut_off() -> Iterator[bytes]:
        yield data[: len(data) // 3]
        raise ConnectionResetError("client went away")

    with pytest.raises((ConnectionResetError, httpx.HTTPError)):
        httpx.post(
            f"{stack.bag_store_url}/api/v1/bags",
            params={"filename": "interrupted.bag"},
            headers={"Authorization": f"Bearer {SERVICE_TOKEN}"},
            content=cut_off(),
        )
    assert _names(stack) == names_before
    assert stack.objects() == before
    wait_until(lambda: not stack.upload_leftovers(), timeout_s=10, what="upload temp files to be removed")


@pytest.mark.parametrize("path", ["..%2F..%2Fmcp", "..%2fmcp", "%2e%2e/%2e%2e/mcp", "bags/..%2F..%2Fmcp"])
def test_the_rest_proxy_never_carries_the_service_token_elsewhere(stack: Stack, path: str) -> None:
    body = {"jsonrpc": "2.0", "id": 1, "method": "tools/list"}
    response = httpx.post(f"{stack.url}/api/v1/{path}", headers=_auth(), json=body)
    assert response.status_code == 404
    assert "tools" not in response.text
