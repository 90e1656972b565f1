"""The processes a `make stack` supervisor started in one directory, found wherever they sit in the process tree,
and stopped: by the watchdog when the supervisor dies without stopping them (SIGKILL, a crash), and by the next
start when they still run (before, that start crash-looped on their bound ports for about 90 s).

The supervisor gives every process it starts ``MEMBER=<stack dir>`` in its environment; children inherit it
(weed under s3.sh, Celery's pool processes), and a process's environment at exec time is readable in
/proc/PID/environ by its owner only, so another user's processes are never matched. A scan of /proc takes
about 10 ms for 400 processes.
"""

from __future__ import annotations

import contextlib
import os
import signal
import time
from collections.abc import Callable
from pathlib import Path

MEMBER = "BAGMCP_STACK_MEMBER"
STOP_TIMEOUT_S = 10.0


def members_of(stack_dir: Path) -> list[int]:
    """Live (not zombie) processes that carry ``stack_dir``'s member mark, lowest pid first."""
    marker = f"{MEMBER}={stack_dir}".encode()
    found = []
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit() or int(entry.name) == os.getpid():
            continue
        with contextlib.suppress(OSError):
            state = (entry / "stat").read_text().rsplit(")", 1)[1].split()[0]
            if state != "Z" and marker in (entry / "environ").read_bytes().split(b"\0"):
                found.append(int(entry.name))
    return sorted(found)


def command_name(pid: int) -> str:
    try:
        return (Path("/proc") / str(pid) / "comm").read_text().strip()
    except OSError:
        return "?"


def _signal_groups(pids: list[int], sig: signal.Signals) -> None:
    """``sig`` to each process's group (a program and what it started), then to the process itself (one that
    left its group)."""
    for pid in pids:
        with contextlib.suppress(ProcessLookupError, PermissionError):
            group = os.getpgid(pid)
            if group != os.getpgrp():  # never the group of whoever is stopping them
                os.killpg(group, sig)
        with contextlib.suppress(ProcessLookupError, PermissionError):
            os.kill(pid, sig)


def stop_members(pids: list[int], *, timeout_s: float = STOP_TIMEOUT_S) -> list[int]:
    """TERM, then KILL what still runs after ``timeout_s`` (weed takes about ten seconds to stop on TERM);
    returns the pids that had to be killed. Only ``pids`` are signalled, never a later scan's: a new stack
    may have started meanwhile."""
    _signal_groups(pids, signal.SIGTERM)
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline and _alive(pids):
        time.sleep(0.1)
    killed = _alive(pids)
    _signal_groups(killed, signal.SIGKILL)
    return killed


def _alive(pids: list[int]) -> list[int]:
    alive = []
    for pid in pids:
        with contextlib.suppress(OSError):
            if (Path("/proc") / str(pid) / "stat").read_text().rsplit(")", 1)[1].split()[0] != "Z":
                alive.append(pid)
    return alive


def stop_leftovers(stack_dir: Path, say: Callable[[str], None], *, whose: str = "an earlier stack") -> int:
    """Stop the processes of ``whose`` stack in ``stack_dir`` that outlived their supervisor, saying which;
    returns how many there were."""
    pids = members_of(stack_dir)
    if pids:
        names = ", ".join(f"{command_name(pid)} ({pid})" for pid in pids)
        say(f"{len(pids)} processes of {whose} in {stack_dir} still run: {names}; stopping them")
        killed = stop_members(pids)
        if killed:
            say(f"{len(killed)} of them did not stop within {STOP_TIMEOUT_S:.0f} s and were killed")
    return len(pids)
