"""The stack's uploads timed as a client makes them (issue 21: upload to ``ready`` under 3x the rosbags
full-decode floor), and what the stack's caches hold on disk against their configured bounds.

Each bag is uploaded with ``bagmcp upload`` and waited for until the gateway's REST API lists it ready
before the next one starts, so one bag's time is not shared with another's ingest; the rows measured
after it are unchanged, since they start once every bag is ready either way."""

from __future__ import annotations

import re
import time
from dataclasses import dataclass
from pathlib import Path

from bagmcp_bag_store.task_refs import INGEST
from bagmcp_shared.settings import Env, TeamSettings
from bench.bags import BenchBag
from bench.restarts import cache_bytes
from tests.integration.stack import Stack

POLL_S = 0.1  # how often the bag's record is read while it ingests (one REST call each)
LOG_WAIT_S = 10.0  # the worker logs the task's end just after it marks the bag ready
_INGESTED = re.compile(rf"Task {re.escape(INGEST.name)}\[[^\]]+\] succeeded in ([0-9.]+)s: 'ready'")


@dataclass(frozen=True)
class UploadTiming:
    """One bag from the start of ``bagmcp upload`` until its record says ready: when the command returned
    (body received, stored in S3, ingest queued), when it was ready, and the worker's own time in the ingest
    task from its Celery log (None when the line was not found)."""

    kind: str
    size_bytes: int
    sent_s: float
    ready_s: float
    ingest_s: float | None = None

    @property
    def mb_per_s(self) -> float:
        return self.size_bytes / 1e6 / self.ready_s


@dataclass(frozen=True)
class CacheUse:
    """One process's cache directory on disk: blocks and the rest (whole copies, local indexes), each with
    the bound the process was configured with."""

    process: str
    blocks: int
    other: int
    blocks_bound: int
    other_bound: int

    @property
    def within(self) -> bool:
        return self.blocks <= self.blocks_bound and self.other <= self.other_bound


def ingest_lines(logs: Path) -> list[float]:
    """The seconds of every successful ingest the bag-store's workers logged, in log order per worker."""
    found: list[float] = []
    for log in sorted(logs.glob("bag-store-worker-*.log")):
        found += [float(m.group(1)) for m in _INGESTED.finditer(log.read_text(errors="replace"))]
    return found


def _new_ingest(logs: Path, before: int) -> float | None:
    """The ingest logged after the first ``before`` ones (waits a little: the line follows the ready mark)."""
    deadline = time.monotonic() + LOG_WAIT_S
    while len(found := ingest_lines(logs)) <= before:
        if time.monotonic() > deadline:
            return None
        time.sleep(POLL_S)
    return found[before] if len(found) == before + 1 else None


def timed_upload(running: Stack, bag: BenchBag, *, timeout_s: float) -> UploadTiming:
    """``bag`` uploaded through the gateway as a client does, then its record read until it is ready."""
    before = len(ingest_lines(running.logs))
    began = time.perf_counter()
    bag_id = running.upload_ok(bag.path)["id"]
    sent_s = time.perf_counter() - began
    while True:
        record = running.rest("GET", f"bags/{bag_id}").json()
        if record["status"] == "ready":
            ready_s = time.perf_counter() - began
            break
        if record["status"] == "failed":
            raise RuntimeError(f"ingest of {bag.path.name} failed: {record['error']}")
        if time.perf_counter() - began > timeout_s:
            raise TimeoutError(f"{bag.path.name} was not ready {timeout_s:g} s after its upload began")
        time.sleep(POLL_S)
    timing = UploadTiming(bag.kind, bag.size_bytes, sent_s, ready_s, _new_ingest(running.logs, before))
    print(f"[bench] stack: {bag.kind} uploaded in {sent_s:.1f} s, ready after {ready_s:.1f} s", flush=True)
    return timing


def cache_use(running: Stack) -> list[CacheUse]:
    """Every service's and worker's cache on disk now, with the bounds their settings give (the stack's
    environment, so a bound set there counts)."""
    settings = TeamSettings.from_env(Env(running.worker_env))
    blocks_bound, other_bound = settings.range_reads.cache_bytes, settings.cache_max_bytes
    dirs = sorted(running.data_dirs.items())
    return [CacheUse(name, *cache_bytes(data), blocks_bound, other_bound) for name, data in dirs]
