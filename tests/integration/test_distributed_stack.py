"""The distributed mode for real: redis-server, weed S3, bag-store, a Celery worker and the gateway
as separate processes; bags uploaded with `bagmcp upload`; tools called through the gateway."""

from __future__ import annotations

import json
import subprocess
import tarfile
import zipfile
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import anyio
import httpx
import pytest
from minio import Minio

from tests.fixtures.bagfactory import BagKind
from tests.fixtures.mcp_client import call, http_client
from tests.fixtures.processes import BIN, http_ok, service, wait_until
from tests.fixtures.servers import S3Endpoint, free_port
from tests.integration.first_tools import check_first_tools

pytestmark = pytest.mark.anyio
TOKEN = "test-client-token"
NAMES = ["scenario", "scenario_db3", "scenario_mcap"]


@dataclass(frozen=True)
class Stack:
    url: str
    bag_store_url: str
    s3: S3Endpoint
    bucket: str
    logs: Path
    bag_store_data: Path


def _env(redis_url: str, s3: S3Endpoint, data: Path, bucket: str) -> dict[str, str]:
    return {
        "BAGMCP_REDIS_URL": redis_url,
        "BAGMCP_S3_ENDPOINT": s3.endpoint,
        "BAGMCP_S3_ACCESS_KEY": s3.access_key,
        "BAGMCP_S3_SECRET_KEY": s3.secret_key,
        "BAGMCP_S3_BUCKET": bucket,
        "BAGMCP_SERVICE_TOKEN": "test-service-token",
        "BAGMCP_DATA_DIR": str(data),
    }


@pytest.fixture(scope="module")
def stack(redis_url: str, s3_server: S3Endpoint, tmp_path_factory: pytest.TempPathFactory) -> Iterator[Stack]:
    logs = tmp_path_factory.mktemp("stack-logs")
    bucket = f"stack-{free_port()}"
    store_port, gateway_port = free_port(), free_port()
    store_data = tmp_path_factory.mktemp("bag-store-data")
    common = _env(redis_url, s3_server, store_data, bucket)
    worker_env = {**common, "BAGMCP_DATA_DIR": str(tmp_path_factory.mktemp("worker-data"))}
    gateway_env = {
        "BAGMCP_SERVICE_TOKEN": "test-service-token",
        "BAGMCP_TOKENS": TOKEN,
        "BAGMCP_PORT": str(gateway_port),
        "BAGMCP_UPSTREAMS": f"bag-store=http://127.0.0.1:{store_port}/mcp",
        "BAGMCP_BAG_STORE_URL": f"http://127.0.0.1:{store_port}",
    }
    store_url = f"http://127.0.0.1:{store_port}"
    worker = [
        str(BIN / "celery"),
        "-A",
        "bagmcp_bag_store.worker:app",
        "worker",
        "--pool",
        "solo",
        "--concurrency",
        "1",
        "--loglevel",
        "INFO",
        "--without-heartbeat",
        "--without-gossip",
    ]
    with (
        service(
            "bag-store",
            [str(BIN / "python"), "-m", "bagmcp_bag_store"],
            env={**common, "BAGMCP_PORT": str(store_port)},
            log_dir=logs,
            ready=http_ok(f"{store_url}/healthz"),
        ),
        service("worker", worker, env=worker_env, log_dir=logs),
        service(
            "gateway",
            [str(BIN / "bagmcp"), "gateway"],
            env=gateway_env,
            log_dir=logs,
            ready=http_ok(f"http://127.0.0.1:{gateway_port}/readyz"),
        ),
    ):
        yield Stack(f"http://127.0.0.1:{gateway_port}", store_url, s3_server, bucket, logs, store_data)


def _upload(stack: Stack, path: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [str(BIN / "bagmcp"), "upload", str(path), "--url", stack.url, "--token", TOKEN, "--json"],
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )


def _objects(stack: Stack) -> list[str]:
    s3 = stack.s3
    client = Minio(s3.endpoint, access_key=s3.access_key, secret_key=s3.secret_key, secure=False)
    return sorted(str(o.object_name) for o in client.list_objects(stack.bucket, recursive=True))


@pytest.fixture(scope="module")
def uploaded(stack: Stack, scenario_bags: dict[BagKind, Path]) -> dict[BagKind, dict[str, object]]:
    answers = {}
    for kind, path in scenario_bags.items():
        result = _upload(stack, path)
        assert result.returncode == 0, result.stderr
        answers[kind] = json.loads(result.stdout)
    return answers


async def _wait_ready(url: str) -> None:
    async with http_client(f"{url}/mcp", TOKEN) as client:
        with anyio.fail_after(90):
            while True:
                bags = (await call(client, "list_bags"))["bags"]
                assert isinstance(bags, list)
                if len(bags) >= len(NAMES) and all(b["status"] == "ready" for b in bags):
                    return
                await anyio.sleep(0.3)


async def test_uploaded_bags_answer_the_first_tools_through_the_gateway(
    stack: Stack, uploaded: dict[BagKind, dict[str, object]]
) -> None:
    assert sorted(str(a["name"]) for a in uploaded.values()) == NAMES
    await _wait_ready(stack.url)
    async with http_client(f"{stack.url}/mcp", TOKEN) as client:
        await check_first_tools(client, NAMES)


async def test_the_ingest_index_and_bag_objects_are_in_s3(
    stack: Stack, uploaded: dict[BagKind, dict[str, object]]
) -> None:
    await _wait_ready(stack.url)
    objects = _objects(stack)
    for answer in uploaded.values():
        assert f"indexes/{answer['id']}/summary.json" in objects
        assert any(o.startswith(f"bags/{answer['id']}/") for o in objects)


def test_uploading_the_same_bag_twice_is_deduplicated(
    stack: Stack, uploaded: dict[BagKind, dict[str, object]], scenario_bags: dict[BagKind, Path]
) -> None:
    again = _upload(stack, scenario_bags["ros1"])
    assert again.returncode == 0, again.stderr
    answer = json.loads(again.stdout)
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
    before = _objects(stack)
    response = httpx.post(
        f"{stack.url}/api/v1/bags",
        params={"filename": label},
        content=content,
        headers={"Authorization": f"Bearer {TOKEN}"},
    )
    assert response.status_code == status
    assert response.json()["error"]["code"] == code
    assert _objects(stack) == before
    names = [
        b["name"]
        for b in httpx.get(f"{stack.url}/api/v1/bags", headers={"Authorization": f"Bearer {TOKEN}"}).json()["bags"]
    ]
    assert sorted(names) == NAMES


def test_a_truncated_bag_is_refused_with_the_reason(
    stack: Stack,
    uploaded: dict[BagKind, dict[str, object]],
    scenario_bags: dict[BagKind, Path],
    tmp_path: Path,
) -> None:
    whole = scenario_bags["ros1"].read_bytes()
    cut = tmp_path / "cut.bag"
    cut.write_bytes(whole[: len(whole) // 2])
    before = _objects(stack)
    result = _upload(stack, cut)
    assert result.returncode == 1
    assert "422" in result.stderr
    assert "cut" in result.stderr
    assert _objects(stack) == before


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
    archive = tmp_path / "zipped_db3.zip"
    with zipfile.ZipFile(archive, "w") as zipped:
        for member in source.iterdir():
            zipped.write(member, f"{source.name}/{member.name}")
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
    before = _objects(stack)
    response = httpx.post(
        f"{stack.url}/api/v1/bags",
        params={"filename": archive.name},
        headers=_auth(),
        content=archive.read_bytes(),
    )
    assert response.status_code == 400
    assert "unsafe path" in response.json()["error"]["message"]
    assert _objects(stack) == before


def test_an_interrupted_upload_leaves_nothing_behind(
    stack: Stack, uploaded: dict[BagKind, dict[str, object]], scenario_bags: dict[BagKind, Path]
) -> None:
    before = _objects(stack)
    data = scenario_bags["ros1"].read_bytes()

    def cut_off() -> Iterator[bytes]:
        yield data[: len(data) // 3]
        raise ConnectionResetError("client went away")

    with pytest.raises((ConnectionResetError, httpx.HTTPError)):
        httpx.post(
            f"{stack.bag_store_url}/api/v1/bags",
            params={"filename": "interrupted.bag"},
            headers={"Authorization": "Bearer test-service-token"},
            content=cut_off(),
        )
    listing = httpx.get(f"{stack.url}/api/v1/bags", headers=_auth()).json()
    assert sorted(b["name"] for b in listing["bags"]) == NAMES
    assert _objects(stack) == before
    uploads = stack.bag_store_data / "uploads"
    wait_until(lambda: not any(uploads.iterdir()), timeout_s=10, what="upload temp files to be removed")
