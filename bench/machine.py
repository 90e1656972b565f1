"""What the figures were measured on."""

from __future__ import annotations

import os
import platform
import subprocess
from dataclasses import dataclass
from pathlib import Path


def _first(path: str, key: str) -> str:
    try:
        for line in Path(path).read_text().splitlines():
            if line.startswith(key):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return "unknown"


@dataclass(frozen=True)
class Machine:
    cores: int
    cpu: str
    memory_gib: float
    python: str
    system: str
    commit: str

    @classmethod
    def here(cls) -> Machine:
        memory_kib = _first("/proc/meminfo", "MemTotal").split()[0]
        commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True, check=False)
        return cls(
            cores=os.cpu_count() or 0,
            cpu=_first("/proc/cpuinfo", "model name"),
            memory_gib=round(int(memory_kib) / 2**20, 1) if memory_kib.isdigit() else 0.0,
            python=platform.python_version(),
            system=platform.platform(),
            commit=commit.stdout.strip() or "unknown",
        )
