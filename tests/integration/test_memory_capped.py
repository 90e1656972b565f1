"""Hostile input against a `bagmcp serve` whose address space is capped at 2 GiB (RLIMIT_AS), far below this
machine's memory: every case answers a clear error, the server lives on, and its peak stays low.

Before the memory budget each case cost more than the cap (so the server answered an internal error or
died; on main it died at its start): the regex a{1000000000} grew a server to 21.9 GB; nested aliases in
metadata.yaml cost 634 MB at 7 levels and ten times more per level (9 here); a 9,500 x 9,500
compressedDepth PNG peaked at 4.4 GB; chunks that expand to 1 GiB (MCAP zstd, ROS 1 bz2, and an MCAP lz4
chunk that declares 1,000 bytes) cost more than twice that in each process that read them. A
zstd-compressed storage file that expands 256 MiB from 8 KB (an earlier bomb, decompressed to disk) is
refused too. The files are kilobytes each, the lz4 one 4 MB (tests/fixtures/hostile_inputs.py). pyarrow's
allocator reserves 1 GiB of address space up front, so the server runs with ARROW_DEFAULT_MEMORY_POOL=system.
"""

from __future__ import annotations

import subprocess
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import httpx
import pytest

from tests.checks.search_checks import search
from tests.fixtures.bagfactory import write_chatter_bag
from tests.fixtures.hostile_inputs import (
    write_big_depth_png,
    write_mcap_chunk_bomb,
    write_ros1_chunk_bomb,
    write_yaml_alias_bomb,
    write_zstd_storage_bomb,
)
from tests.fixtures.mcp_client import call_error, http_client, ingested_bags
from tests.fixtures.processes import BIN, capped_address_space, http_ok, peak_memory_kib, service
from tests.fixtures.servers import free_port

pytestmark = pytest.mark.anyio
CAP_BYTES = 2 << 30
BOMB_BYTES = 1 << 30
CAPPED_ENV = {"ARROW_DEFAULT_MEMORY_POOL": "system", "MALLOC_ARENA_MAX": "2"}
REGEX_BOMBS = ["a{1000000000}", "(?:a{1000}){1000}", "a{2000000}", "((a{100}){100}){100}"]


@dataclass(frozen=True)
class Capped:
    url: str
    process: subprocess.Popen[bytes]
    folder: Path


@pytest.fixture(scope="module")
def hostile_folder(tmp_path_factory: pytest.TempPathFactory) -> Path:
    folder = tmp_path_factory.mktemp("hostile") / "bags"
    folder.mkdir()
    write_mcap_chunk_bomb(folder / "mcap_chunk_bomb.mcap", expanded=BOMB_BYTES)
    write_mcap_chunk_bomb(folder / "mcap_lz4_lie.mcap", expanded=BOMB_BYTES, compression="lz4", declared=1000)
    write_ros1_chunk_bomb(folder, expanded=BOMB_BYTES)
    write_yaml_alias_bomb(folder, levels=9)
    write_big_depth_png(folder, side=9500)
    write_zstd_storage_bomb(folder, expanded=256 << 20)
    write_chatter_bag(folder, count=20)
    return folder


@pytest.fixture(scope="module")
def capped(hostile_folder: Path, tmp_path_factory: pytest.TempPathFactory) -> Iterator[Capped]:
    port = free_port()
    url = f"http://127.0.0.1:{port}"
    data = tmp_path_factory.mktemp("data")
    command = [str(BIN / "bagmcp"), "serve", "--bags", str(hostile_folder), "--port", str(port), "--data", str(data)]
    with service(
        "capped-serve",
        command,
        env=CAPPED_ENV,
        log_dir=tmp_path_factory.mktemp("logs"),
        ready=http_ok(f"{url}/healthz"),
        address_space_bytes=CAP_BYTES,
    ) as process:
        yield Capped(url, process, hostile_folder)


def _listed(url: str) -> dict[str, tuple[str, str | None]]:
    bags = httpx.get(f"{url}/api/v1/bags", timeout=30).json()["bags"]
    return {b["name"]: (b["status"], b["error"]) for b in bags}


async def _ingested(url: str) -> dict[str, tuple[str, str | None]]:
    """Each bag's status and error (from REST, which carries the error) once none is ingesting."""
    async with http_client(f"{url}/mcp", None) as client:
        await ingested_bags(client, timeout_s=60)
    return _listed(url)


async def test_stored_bombs_fail_their_ingest_with_a_sentence_naming_the_record(capped: Capped) -> None:
    listed = await _ingested(capped.url)
    assert listed["chatter"][0] == "ready"
    assert listed["big_depth_png"][0] == "ready"
    status, error = listed["mcap_chunk_bomb"]
    assert status == "failed"
    assert "the zstd chunk at byte 36 declares 1,073,741,9" in str(error)
    assert "refused as a decompression bomb" in str(error)
    status, error = listed["mcap_lz4_lie"]
    assert status == "failed"
    assert "an lz4 chunk holds more than 268,435,456 bytes uncompressed" in str(error)
    status, error = listed["ros1_chunk_bomb"]
    assert status == "failed"
    assert "the bz2 chunk at byte 4,109 declares 1,073,742," in str(error)
    status, error = next(v for name, v in listed.items() if name.startswith("yaml_alias_bomb"))
    assert status == "failed"
    assert "metadata.yaml uses the YAML alias *l0 at line 2" in str(error)
    status, error = listed["scenario-sqlite3-zstd-file"]
    assert status == "failed"
    assert "expands more than 200 times when decompressed" in str(error)
    assert capped.process.poll() is None


async def test_regex_bombs_are_refused_before_compiling(capped: Capped) -> None:
    await _ingested(capped.url)
    async with http_client(f"{capped.url}/mcp", None) as client:
        for pattern in REGEX_BOMBS:
            error = await call_error(
                client, "search_messages", bag="chatter", topic="/chatter", condition="regex", value=pattern
            )
            assert "RE2 allows repeat counts up to 1000" in error, error
        found = await search(client, bag="chatter", topic="/chatter", condition="regex", value="lo 1[0-9]$")
        assert found["total"] == 10, found
    assert capped.process.poll() is None


async def test_an_image_past_the_pixel_budget_is_refused_before_decoding(capped: Capped) -> None:
    await _ingested(capped.url)
    async with http_client(f"{capped.url}/mcp", None) as client:
        error = await call_error(client, "get_image_at_time", bag="big_depth_png", topic="/depth", time=0)
    assert "9,500 x 9,500 pixels" in error, error
    assert "BAGMCP_MAX_IMAGE_BYTES" in error
    assert capped.process.poll() is None


INFO_REFUSALS = {
    "mcap_chunk_bomb.mcap": "the zstd chunk at byte 36 declares 1,073,741,9",
    "mcap_lz4_lie.mcap": "an lz4 chunk holds more than 268,435,456 bytes uncompressed in 4,",
    "ros1_chunk_bomb.bag": "the bz2 chunk at byte 4,109 declares 1,073,742,",
    "yaml_alias_bomb*/": "metadata.yaml uses the YAML alias *l0 at line 2; it is refused to bound memory",
    "scenario-sqlite3-zstd-file/": "zstd: expands more than 200 times when decompressed; refusing it as a",
}


@pytest.mark.parametrize("name", INFO_REFUSALS)
def test_bagmcp_info_refuses_the_chunk_bombs_in_one_line(hostile_folder: Path, name: str) -> None:
    """Each bomb, files and bag directories alike, is refused by `bagmcp info` under the same 2 GiB cap with
    one line on stderr (exit status 1, no traceback): the lz4 chunk that declares 1,000 bytes is stopped at
    256 MiB, the alias bomb before rosbags parses metadata.yaml, the storage file while it is decompressed."""
    bag = next(hostile_folder.glob(name.rstrip("/")))
    assert bag.is_dir() == name.endswith("/")
    done = subprocess.run(
        [str(BIN / "bagmcp"), "info", str(bag)],
        capture_output=True,
        text=True,
        timeout=60,
        env={**CAPPED_ENV, "PATH": "/usr/bin:/bin"},
        preexec_fn=capped_address_space(CAP_BYTES),
        check=False,
    )
    assert done.returncode == 1, done.stderr[-2000:]
    assert done.stdout == ""
    assert done.stderr.count("\n") == 1, done.stderr[-2000:]
    assert done.stderr.startswith(f"bagmcp: error: {bag}")
    assert INFO_REFUSALS[name] in done.stderr, done.stderr
    assert "Traceback" not in done.stderr


async def test_the_server_stayed_under_its_cap_after_every_case(capped: Capped) -> None:
    """Runs last in this file: the whole run's peak resident memory, read from /proc while the server still
    runs, is far below the cap (the address space cannot pass it; what counts is that nothing tried)."""
    await _ingested(capped.url)
    peak = peak_memory_kib(capped.process.pid)
    assert capped.process.poll() is None
    assert peak["VmHWM"] < 1 << 20, peak  # KiB: under 1 GiB resident
    print(f"capped server peaks: address space {peak['VmPeak'] >> 10} MiB, resident {peak['VmHWM'] >> 10} MiB")
