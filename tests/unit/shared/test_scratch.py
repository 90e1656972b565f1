"""Scratch directories: a process's own, and what processes that died left behind removed by the next one."""

from __future__ import annotations

import os
import socket
import subprocess
import tempfile
from pathlib import Path

from bagmcp_shared.scratch import own_scratch, process_tag, remove_dead, use_scratch


def _dead_pid() -> int:
    child = subprocess.Popen(["true"])
    child.wait()
    return child.pid


def test_what_dead_processes_of_this_host_left_is_removed_and_nothing_else(tmp_path: Path) -> None:
    host = socket.gethostname()
    dead = tmp_path / f"{host}~{_dead_pid()}"
    (dead / "nested").mkdir(parents=True)
    (dead / "nested" / "body").write_bytes(b"half an upload")
    alive = tmp_path / f"{host}~{os.getppid()}"
    other_host = tmp_path / f"another-machine~{_dead_pid()}"
    unrelated = tmp_path / "notes"
    for kept in (alive, other_host, unrelated):
        kept.mkdir()
    assert remove_dead(tmp_path) == [dead.name]
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted([alive.name, other_host.name, "notes"])


def test_a_process_gets_its_own_scratch_and_its_temporary_files_go_there(tmp_path: Path) -> None:
    before = tempfile.tempdir
    try:
        mine = use_scratch(tmp_path / "scratch")
        assert mine == tmp_path / "scratch" / process_tag()
        with tempfile.TemporaryDirectory() as work:
            assert Path(work).parent == mine
    finally:
        tempfile.tempdir = before
    assert own_scratch(tmp_path / "scratch") == mine  # the same on a second call, and kept
