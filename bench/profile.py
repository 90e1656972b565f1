"""py-spy on a serving process while work runs, boiled down to where the time goes."""

from __future__ import annotations

import re
import signal
import subprocess
import time
from collections import Counter
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

from tests.fixtures.processes import BIN

_LINE = re.compile(r"^(?P<stack>.*) (?P<count>\d+)$")
_FRAME = re.compile(r"^(?P<function>.*?) \((?P<file>.*?)(?::\d+)?\)$")
PROJECT = "bagmcp_"
MIN_SAMPLES = 20  # a process that sampled less than this did not take part (a worker idle for inline work)
# Threads parked in these are waiting, not working (py-spy's idle detection misses some of them).
WAITING = (
    "Condition.wait (threading.py)",
    "_worker (concurrent/futures/thread.py)",
    "select (selectors.py)",
    "dequeue (logging/handlers.py)",
    "_read_from_socket (redis/_parsers/socket.py)",
    "_epoll.poll (kombu/utils/eventio.py)",
)


@dataclass(frozen=True)
class Hotspot:
    frame: str
    self_pct: float
    total_pct: float


@dataclass(frozen=True)
class Profile:
    """What one process spent its sampled (non-idle) time on while ``label`` ran."""

    label: str
    process: str
    samples: int
    top_self: list[Hotspot]
    top_project: list[Hotspot]


@contextmanager
def recording(pid: int, out: Path, *, rate_hz: int = 250) -> Iterator[None]:
    """``py-spy record`` (all threads, idle ones left out) on ``pid`` until the block ends."""
    command = [str(BIN / "py-spy"), "record", "-p", str(pid), "-o", str(out), "-f", "raw", "-r", str(rate_hz)]
    with (out.parent / f"{out.name}.log").open("wb") as log:
        proc = subprocess.Popen(command, stdout=log, stderr=subprocess.STDOUT)
        time.sleep(1.0)  # attached before the work starts
        try:
            yield
        finally:
            proc.send_signal(signal.SIGINT)  # py-spy writes its file when interrupted
            proc.wait(timeout=60)


def _short(frame: str) -> str:
    found = _FRAME.match(frame)
    if found is None:
        return frame
    path = found["file"]
    if "site-packages/" in path:
        path = path.split("site-packages/", 1)[1]
    elif PROJECT in path:
        path = path[path.index(PROJECT) :]
    return f"{found['function']} ({path})"


def summarize(raw: Path, *, label: str, process: str, limit: int = 12) -> Profile:
    """Top frames by own time, and the project's frames by time spent inside them (callees included)."""
    own: Counter[str] = Counter()
    inside: Counter[str] = Counter()
    total = 0
    text = raw.read_text(errors="replace") if raw.exists() else ""
    for line in text.splitlines():
        found = _LINE.match(line)
        if found is None:
            continue
        count = int(found["count"])
        frames = [_short(f) for f in found["stack"].split(";")]
        if frames[-1].endswith(WAITING):
            continue
        total += count
        own[frames[-1]] += count
        for frame in set(frames):
            if PROJECT in frame:
                inside[frame] += count

    def hot(counter: Counter[str]) -> list[Hotspot]:
        return [
            Hotspot(frame, 100 * own[frame] / total, 100 * inside.get(frame, own[frame]) / total)
            for frame, _ in counter.most_common(limit)
        ]

    return Profile(label, process, total, hot(own) if total else [], hot(inside) if total else [])
