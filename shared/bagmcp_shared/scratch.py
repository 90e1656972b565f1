"""Scratch space of one process under a data directory (``<root>/<host>~<pid>``): temporary files, upload
bodies, unpacked archives, indexes being built. A process killed outright leaves its scratch behind; the
next process that starts on the same host over the same root removes it, so nothing piles up.

Entries are named by host and process id so processes of several machines or containers sharing a volume
never remove each other's.
"""

from __future__ import annotations

import os
import shutil
import socket
import tempfile
from pathlib import Path

_SEPARATOR = "~"


def process_tag() -> str:
    return f"{socket.gethostname()}{_SEPARATOR}{os.getpid()}"


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def _left_by_the_dead(name: str) -> bool:
    host, separator, pid = name.rpartition(_SEPARATOR)
    return bool(separator) and host == socket.gethostname() and pid.isdigit() and not _alive(int(pid))


def remove_dead(root: Path) -> list[str]:
    """Remove the entries under ``root`` of processes of this host that no longer run; returns their names."""
    if not root.is_dir():
        return []
    removed = []
    for entry in root.iterdir():
        if _left_by_the_dead(entry.name):
            shutil.rmtree(entry, ignore_errors=True) if entry.is_dir() else entry.unlink(missing_ok=True)
            removed.append(entry.name)
    return removed


def own_scratch(root: Path) -> Path:
    """This process's scratch directory under ``root`` (made, and what dead processes left there removed)."""
    remove_dead(root)
    mine = root / process_tag()
    mine.mkdir(parents=True, exist_ok=True)
    return mine


def use_scratch(root: Path) -> Path:
    """``own_scratch``, also made the directory of every temporary file of this process."""
    mine = own_scratch(root)
    tempfile.tempdir = str(mine)
    return mine
