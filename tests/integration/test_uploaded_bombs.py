"""Bombs uploaded to the stack, where issue 18 found them (an uploaded ROS 2 directory whose metadata.yaml
nests aliases, an MCAP whose zstd chunk declares 512 MiB) are refused at the upload with the sentence that
names the record, before anything is expanded and before anything is stored (before the budget both were
accepted, and the bag-store and its worker each grew 1.3 GB on the chunk). The bombs here are small forms of
the reproductions (4 alias levels, a chunk of 512 MiB of zeros that is 16 KB compressed); the memory-capped
suite sends the large ones."""

from __future__ import annotations

from pathlib import Path

import httpx

from tests.fixtures.archives import zip_directory
from tests.fixtures.hostile_inputs import write_mcap_chunk_bomb, write_yaml_alias_bomb
from tests.integration.stack import Stack


def _send(stack: Stack, path: Path, name: str) -> httpx.Response:
    with path.open("rb") as body:
        return stack.rest("POST", "bags", params={"filename": path.name, "name": name}, content=body)


def test_an_uploaded_alias_bomb_is_refused_at_once_naming_the_alias(stack: Stack, tmp_path: Path) -> None:
    directory = write_yaml_alias_bomb(tmp_path, levels=4)
    answer = _send(stack, zip_directory(directory, tmp_path / "alias.zip"), "uploaded_alias_bomb")
    assert answer.status_code == 422, answer.text[:300]
    error = answer.json()["error"]
    assert error["code"] == "invalid_bag"
    assert error["message"].startswith("alias.zip: metadata.yaml uses the YAML alias *l0 at line 2; it is refused")
    assert "uploaded_alias_bomb" not in stack.bags()


def test_an_uploaded_chunk_bomb_is_refused_at_once_naming_the_chunk(stack: Stack, tmp_path: Path) -> None:
    answer = _send(stack, write_mcap_chunk_bomb(tmp_path / "chunk.mcap", expanded=512 << 20), "uploaded_chunk_bomb")
    assert answer.status_code == 422, answer.text[:300]
    error = answer.json()["error"]
    assert error["code"] == "invalid_bag"
    assert (
        "the zstd chunk at byte 36 declares 536,871,036 bytes uncompressed from 16,498 compressed" in error["message"]
    )
    assert "refused as a decompression bomb" in error["message"]
    assert "uploaded_chunk_bomb" not in stack.bags()
