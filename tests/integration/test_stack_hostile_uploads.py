"""Hostile and damaged uploads through the gateway of the running stack: clear refusals in the one error
shape, nothing stored, no temporary files left; exact names for deletes; failures listed with their reason."""

from __future__ import annotations

from pathlib import Path

import pytest

from tests.fixtures.archives import write_zip_bomb, zip_directory
from tests.fixtures.bagfactory import BagKind, write_chatter_bag
from tests.fixtures.compressed_bags import write_compressed
from tests.fixtures.damage import corrupt_mcap_chunk
from tests.fixtures.mcap_cuts import write_mcap
from tests.fixtures.mcp_client import call, http_client
from tests.fixtures.processes import wait_until
from tests.integration.stack import TOKEN, Stack

pytestmark = pytest.mark.anyio


def _post(stack: Stack, path: Path, filename: str | None = None) -> tuple[int, dict[str, object]]:
    with path.open("rb") as body:
        answer = stack.rest("POST", "bags", params={"filename": filename or path.name}, content=body)
    return answer.status_code, answer.json()


def _error(body: dict[str, object]) -> dict[str, str]:
    error = body["error"]
    assert isinstance(error, dict)
    return error


def test_an_mcap_whose_first_chunk_does_not_decompress_is_refused_with_422(stack: Stack, tmp_path: Path) -> None:
    damaged = tmp_path / "damaged_zstd.mcap"
    write_mcap(damaged, "zstd")
    corrupt_mcap_chunk(damaged, 0)
    before, listed = stack.objects(), stack.bags()
    status, body = _post(stack, damaged)
    assert status == 422
    error = _error(body)
    assert error["code"] == "invalid_bag"
    assert error["message"].startswith("damaged_zstd.mcap: ")
    assert "damaged" in error["message"]
    assert "/tmp" not in error["message"]
    assert stack.objects() == before
    assert stack.bags().keys() == listed.keys()
    assert stack.upload_leftovers() == []


async def test_a_bag_damaged_past_what_upload_reads_is_listed_failed_with_the_reason(
    stack: Stack, tmp_path: Path
) -> None:
    bag = write_compressed("mcap-lz4", tmp_path)  # five chunks; upload reads the first and the last
    corrupt_mcap_chunk(bag, 1)
    answer = stack.upload_ok(bag, name="lz4_chunk_damaged")
    wait_until(lambda: stack.bags()["lz4_chunk_damaged"]["status"] != "ingesting", timeout_s=60, what="ingest")
    async with http_client(f"{stack.url}/mcp", TOKEN) as client:
        listed = (await call(client, "list_bags", name="lz4_chunk_damaged"))["bags"]
    assert [(b["id"], b["status"]) for b in listed] == [(answer["id"], "failed")]
    assert listed[0]["error"].startswith("lz4_chunk_damaged: a chunk could not be read (LZ4F_")
    assert "/" not in listed[0]["error"].split(":")[0]  # the bag's name, no server path


def test_a_zip_bomb_next_to_a_real_bag_is_refused_and_leaves_nothing(
    stack: Stack, scenario_bags: dict[BagKind, Path], tmp_path: Path
) -> None:
    bomb = write_zip_bomb(tmp_path / "bomb.zip", scenario_bags["ros2-mcap"], zeros_mib=2048)
    assert bomb.stat().st_size < 3 << 20
    before, listed = stack.objects(), stack.bags()
    status, body = _post(stack, bomb)
    assert status == 413
    error = _error(body)
    assert error["code"] == "upload_too_large"
    assert "the archive unpacks to more than" in error["message"]
    assert stack.objects() == before
    assert stack.bags().keys() == listed.keys()
    assert stack.upload_leftovers() == []


def test_an_archive_stores_only_the_bags_own_files_and_says_what_it_left_out(
    stack: Stack, uploaded: dict[BagKind, dict[str, object]], scenario_bags: dict[BagKind, Path], tmp_path: Path
) -> None:
    source = scenario_bags["ros2-sqlite3"]
    extras: dict[str, bytes | str] = {f"{source.name}/notes.txt": "slow today", "__MACOSX/._metadata.yaml": bytes(10)}
    archive = zip_directory(source, tmp_path / "with_extras.zip", extras=extras)
    status, body = _post(stack, archive)
    assert status == 200  # the same bag as the sqlite3 upload: the extras are not part of its content
    assert body["duplicate"] is True
    assert isinstance(body["bag"], dict)
    assert body["bag"]["id"] == uploaded["ros2-sqlite3"]["id"]
    assert body["notes"] == [
        f"{source.name}/notes.txt was left out: it is not part of a bag",
        "__MACOSX/._metadata.yaml was left out: it is not part of a bag",
    ]
    assert stack.upload_leftovers() == []


async def test_delete_takes_an_exact_name_and_the_same_bytes_upload_again_under_another_name(
    stack: Stack, tmp_path: Path
) -> None:
    bag = write_chatter_bag(tmp_path, count=200, name="outing")
    first = stack.upload_ok(bag)
    await stack.wait_ready(["outing"])
    async with http_client(f"{stack.url}/mcp", TOKEN) as client:
        await call(client, "get_message_at_time", bag="outing", topic="/chatter", time=0.05)  # cached by bag-store
        prefix = stack.rest("DELETE", "bags/outin")  # not "out": the session stack may hold the corpus's "out"
        assert prefix.status_code == 404
        assert _error(prefix.json())["code"] == "bag_not_found"
        assert stack.rest("GET", "bags/outing").status_code == 200
        assert stack.rest("DELETE", "bags/outing").status_code == 204
        assert stack.rest("GET", "bags/outing").status_code == 404
        assert not [o for o in stack.objects() if first["id"] in o]
        again = stack.upload_ok(bag, name="outing_again")
        assert (again["id"], again["duplicate"]) == (first["id"], False)
        await stack.wait_ready(["outing_again"])
        found = await call(client, "get_message_at_time", bag="outing_again", topic="/chatter", time=0.05)
    assert found["message"]["data"]["data"] == "hello 50"


def test_a_token_sent_in_a_query_string_never_reaches_a_log(stack: Stack) -> None:
    secret = "leaky-secret-7d1f"
    answer = stack.rest("GET", "bags", params={"token": secret, "limit": 1})
    assert answer.status_code == 200
    logs = {p.name: p.read_text(errors="replace") for p in stack.logs.glob("*.log")}
    assert any("token=REDACTED" in text for text in logs.values())  # the request was logged, redacted
    assert [name for name, text in logs.items() if secret in text] == []
