"""The upload-to-ready pieces that need no stack: the worker's ingest time read from its Celery log, and the
issue 21 rows of the page (upload to ready against 3x the full-decode floor, caches against their bounds)."""

from __future__ import annotations

from pathlib import Path

from bench.bags import BenchBag
from bench.floors import FLOORS, FULL_DECODE
from bench.machine import Machine
from bench.report import render
from bench.results import RunResult
from bench.stats import Timing
from bench.uploads import CacheUse, UploadTiming, ingest_lines

GB = 10**9
GIB = 2**30


def test_the_ingest_time_is_read_from_the_workers_celery_log(tmp_path: Path) -> None:
    task = "Task bagmcp.bag_store.ingest[3c830992-88c9-4939-8a79-b088f47c3bc5]"
    (tmp_path / "bag-store-worker-1.log").write_text(
        f"[2026-11-27 20:16:23,563: INFO/MainProcess] {task} received\n"
        f"[2026-11-27 20:16:23,609: INFO/MainProcess] {task} succeeded in 0.045687806999978875s: 'failed'\n"
        f"[2026-11-27 20:16:30,001: INFO/MainProcess] {task} succeeded in 12.5s: 'ready'\n"
        "[2026-11-27 20:16:31,000: INFO/MainProcess] Task bagmcp.bag_store.run_job[x] succeeded in 2.0s: 'ready'\n"
    )
    (tmp_path / "analysis-worker-2.log").write_text(f"{task} succeeded in 9.0s: 'ready'\n")
    assert ingest_lines(tmp_path) == [12.5]  # failed ingests, other tasks and other services' logs left out
    assert ingest_lines(tmp_path / "missing") == []


def test_the_page_judges_upload_to_ready_and_the_caches_against_their_bounds(tmp_path: Path) -> None:
    bags = [
        BenchBag("ros1", tmp_path / "drive.bag", 2 * GB, 200.0),
        BenchBag("ros2-mcap", tmp_path / "m", 2 * GB, 200.0),
    ]
    floors: dict[str, dict[str, Timing]] = {
        b.kind: {f.key: Timing([2000.0 if f.key == FULL_DECODE else 10.0]) for f in FLOORS} for b in bags
    }
    run = RunResult(Machine(2, "test cpu", 4.0, "3.11", "linux", "abc"), False, 3, bags, floors)
    run.uploads = [UploadTiming("ros1", 2 * GB, 2.0, 5.0, 2.5), UploadTiming("ros2-mcap", 2 * GB, 3.0, 8.0)]
    worker = CacheUse("bag-store-worker-1", 2 * GB, 300_000, 4 * GIB, 20 * GIB)
    run.caches = [
        ("after the uploads", [CacheUse("bag-store", 0, 0, 4 * GIB, 20 * GIB), worker]),
        ("after the warm calls and loads", [CacheUse("analysis", 5 * GIB, 0, 4 * GIB, 20 * GIB), worker]),
    ]
    page = render(run, notes="")
    rows = [line for line in page.splitlines() if line.startswith(("| stack upload", "| stack caches"))]
    assert rows == [
        "| stack upload to ready < 3x floor (open + decode every message) | ros1 | 5.00 s (400 MB/s, 2.50x) "
        "| 6.00 s | met |",
        "| stack upload to ready < 3x floor (open + decode every message) | ros2-mcap | 8.00 s (250 MB/s, 4.00x) "
        "| 6.00 s | **missed** |",
        "| stack caches on disk within their bounds, after the uploads | all | 2,000 MB in 2 processes "
        "| 51,540 MB | met |",
        "| stack caches on disk within their bounds, after the warm calls and loads | all | 7,369 MB in 2 processes "
        "| 51,540 MB | **missed** |",
    ]
    assert "| ros1 | 2,000 | 2.00 | 5.00 | 400 | 2.50 | 2.00 | 2.50 | met |" in page
    assert "| ros2-mcap | 2,000 | 3.00 | 8.00 | 250 |  | 2.00 | 4.00 | **missed** |" in page
    assert "| analysis | 5,369 | 4,295 | 0.00 | 21,475 | **missed** |" in page
    assert "| together | 7,369 | 8,590 | 0.30 | 42,950 | **missed** |" in page
    assert "| open + decode every message | 2,000 | 2,000 |" in page
