"""Fresh service processes for cold calls on the stack: the three services and their workers stopped and
started again on the same ports, each with a new, empty data directory (so no block cache, whole copy,
local index or opened bag survives), reading S3 through a chosen endpoint (the delay proxy); Redis, weed
and the gateway keep running. Also what they fetched (/metrics) and what their caches hold on disk."""

from __future__ import annotations

import os
import shutil
import signal
import subprocess
import threading
from collections.abc import Iterator
from contextlib import contextmanager, suppress
from pathlib import Path

import httpx

from tests.fixtures.processes import BIN, wait_until
from tests.integration.stack import SERVICES, WORKER_FLAGS, Stack, service_counters

START_TIMEOUT_S = 120.0
FETCHED = "bagmcp_s3_fetched_bytes_total"


class FreshServices:
    """Restarts the stack's services and workers; ``data`` holds the current processes' data directories."""

    def __init__(self, running: Stack, work: Path) -> None:
        self._running = running
        self._work = work
        self._current: dict[str, subprocess.Popen[bytes]] = {name: running.processes[name] for name in SERVICES}
        self._current.update({f"{of} worker": proc for of, proc in running.workers})
        self._count = 0
        self.data: dict[str, Path] = {}

    def restart(self, *, s3_endpoint: str, env: dict[str, str] | None = None) -> None:
        """Stop every service and worker, drop the last fresh data directories, start them all again."""
        self._kill()
        for directory in self.data.values():
            shutil.rmtree(directory, ignore_errors=True)
        self._count += 1
        base = self._work / f"fresh-{self._count}"
        common = {**self._running.worker_env, "BAGMCP_S3_ENDPOINT": s3_endpoint, **(env or {})}
        logs = self._running.logs
        self.data = {name: base / name.replace(" ", "-") for name in self._current}
        started: dict[str, subprocess.Popen[bytes]] = {}
        for name, package in SERVICES.items():
            port = self._running.service_urls[name].rsplit(":", 1)[1]
            command = [str(BIN / "python"), "-m", package]
            started[name] = _spawn(command, {**common, "BAGMCP_PORT": port}, self.data[name], logs / f"{name}.log")
            worker = f"{name} worker"
            command = [str(BIN / "celery"), "-A", f"{package}.worker:app", *WORKER_FLAGS]
            started[worker] = _spawn(command, common, self.data[worker], logs / f"{worker.replace(' ', '-')}.log")
        self._current = started
        wait_until(self._all_up, timeout_s=START_TIMEOUT_S, what="the restarted services and workers")

    def pid(self, name: str) -> int:
        """The process id of a current service or worker (``bag-store``, ``bag-store worker``, ...)."""
        return self._current[name].pid

    def close(self) -> None:
        self._kill()

    def _kill(self) -> None:
        """SIGKILL to every process group at once: their data is thrown away, and a graceful stop waits for
        the gateway's kept-alive connections (10 s each)."""
        for proc in self._current.values():
            if proc.poll() is None:
                with suppress(ProcessLookupError):
                    os.killpg(proc.pid, signal.SIGKILL)
        for proc in self._current.values():
            proc.wait(timeout=30)

    def fetched_bytes(self) -> int:
        """Bytes the services' own block caches fetched from S3 since their start (/metrics, process="service";
        their workers' sums are not counted here)."""
        return sum(service_counters(url)["service"][FETCHED] for url in self._running.service_urls.values())

    def _all_up(self) -> bool:
        for name, proc in self._current.items():
            if proc.poll() is not None:
                raise RuntimeError(f"{name} exited with {proc.returncode} after a restart; see its log")
        for url in self._running.service_urls.values():
            try:
                if httpx.get(f"{url}/healthz", timeout=2).status_code != 200:
                    return False
            except httpx.HTTPError:
                return False
        logs = self._running.logs
        return all(
            " ready." in (logs / f"{name.replace(' ', '-')}.log").read_text(errors="replace")
            for name in self._current
            if name.endswith("worker")
        )


def _spawn(command: list[str], env: dict[str, str], data: Path, log: Path) -> subprocess.Popen[bytes]:
    data.mkdir(parents=True)
    with log.open("wb") as out:  # a new log per restart: readiness is read from it
        return subprocess.Popen(
            command,
            env={**os.environ, **env, "BAGMCP_DATA_DIR": str(data)},
            stdout=out,
            stderr=subprocess.STDOUT,
            start_new_session=True,
        )


def cache_bytes(data: Path) -> tuple[int, int]:
    """(bytes of blocks, bytes of everything else) under one process's ``$BAGMCP_DATA_DIR/cache``: the
    block cache (``.blocks/blocks``), and whole copies of bags with the local indexes."""
    blocks = copies = 0
    root = data / "cache"
    for directory, _, files in os.walk(root):
        in_blocks = Path(directory).is_relative_to(root / ".blocks" / "blocks")
        in_other_block_files = not in_blocks and Path(directory).is_relative_to(root / ".blocks")
        for name in files:
            with suppress(FileNotFoundError):
                size = (Path(directory) / name).stat().st_size
                if in_blocks:
                    blocks += size
                elif not in_other_block_files:
                    copies += size
    return blocks, copies


@contextmanager
def disk_peaks(fresh: FreshServices, *, every_s: float = 0.1) -> Iterator[dict[str, tuple[int, int]]]:
    """While the block runs, the most each process's cache held on disk (blocks, other), sampled."""
    peaks: dict[str, tuple[int, int]] = {}
    done = threading.Event()

    def sample() -> None:
        while True:
            for name, data in list(fresh.data.items()):
                blocks, copies = cache_bytes(data)
                old = peaks.get(name, (0, 0))
                peaks[name] = (max(old[0], blocks), max(old[1], copies))
            if done.wait(every_s):
                return

    thread = threading.Thread(target=sample, name="disk-peaks", daemon=True)
    thread.start()
    try:
        yield peaks
    finally:
        done.set()
        thread.join(30)
