"""What the figures were measured on."""

from __future__ import annotations

import os
import platform
import statistics
import subprocess
import threading
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


class LoadWatch:
    """The machine's 1-minute load average every ``every_s`` while the run goes, by phase: the cores are
    shared, and a figure measured while other work ran says so on the page."""

    def __init__(self, *, every_s: float = 10.0) -> None:
        self.phase = "start"
        self.samples: list[tuple[str, float]] = []
        self._every_s = every_s
        self._done = threading.Event()
        self._thread = threading.Thread(target=self._sample, name="load-watch", daemon=True)

    def __enter__(self) -> LoadWatch:
        self._thread.start()
        return self

    def __exit__(self, *_: object) -> None:
        self._done.set()
        self._thread.join(5)

    def _sample(self) -> None:
        while True:
            self.samples.append((self.phase, os.getloadavg()[0]))
            if self._done.wait(self._every_s):
                return


def load_by_phase(samples: list[tuple[str, float]]) -> list[tuple[str, float, float]]:
    """(phase, median, max) of the load samples, phases in the order they began."""
    phases: dict[str, list[float]] = {}
    for phase, load in samples:
        phases.setdefault(phase, []).append(load)
    return [(phase, statistics.median(loads), max(loads)) for phase, loads in phases.items()]
