"""The cold passes' pieces that need no stack: answers compared without what legitimately differs, the
caches' disk use split into blocks and the rest, and the issue 21 rows of the page (met and missed)."""

from __future__ import annotations

from pathlib import Path

from bench.bags import BenchBag
from bench.calls import CALLS
from bench.cold import ColdPass, ColdResult, comparable
from bench.delay_proxy import ProxyCounts
from bench.floors import FLOORS
from bench.machine import Machine
from bench.report import render
from bench.restarts import cache_bytes
from bench.results import RunResult
from bench.stats import Timing

GB = 2 * 10**9


def test_answers_compare_without_job_ids_links_and_the_output_name() -> None:
    arguments = {"bag": "drive", "name": "drive-cut-20-cold"}
    one = {"bag": "drive-cut-20-cold", "job": "j1", "url": "http://a", "rows": [{"x": 1.0}]}
    other = {"url": "http://b", "bag": "drive-cut-20-quarter", "job": "j2", "rows": [{"x": 1.0}]}
    assert comparable(one, arguments) == comparable(other, {**arguments, "name": "drive-cut-20-quarter"})
    assert comparable(one, arguments) != comparable({**one, "rows": [{"x": 2.0}]}, arguments)


def test_cache_bytes_counts_blocks_apart_from_copies_and_leaves_out_lock_files(tmp_path: Path) -> None:
    blocks = tmp_path / "cache" / ".blocks"
    (blocks / "blocks" / "obj").mkdir(parents=True)
    (blocks / "blocks" / "obj" / "0").write_bytes(b"b" * 1000)
    (blocks / "blocks" / "obj" / "1").write_bytes(b"b" * 24)
    (blocks / "locks").mkdir()
    (blocks / "locks" / "7").write_bytes(b"l" * 50)
    (tmp_path / "cache" / "bag").mkdir()
    (tmp_path / "cache" / "bag" / "x.db3").write_bytes(b"c" * 300)
    assert cache_bytes(tmp_path) == (1024, 300)
    assert cache_bytes(tmp_path / "missing") == (0, 0)


def _result(label: str, cold_ms: float, *, answered: int = 0, differs: str | None = None) -> ColdResult:
    call = next(c for c in CALLS if c.label == label)
    return ColdResult(call, Timing([cold_ms]), Timing([5.0]), cold_s3=ProxyCounts(4, 900, answered), differs=differs)


def test_the_page_judges_the_stack_cold_targets_per_format(tmp_path: Path) -> None:
    bags = [BenchBag("ros2-mcap", tmp_path / "drive_mcap", GB, 200.0)]
    floors = {"ros2-mcap": {f.key: Timing([100.0]) for f in FLOORS}}
    cold = ColdPass("cold", 0.0)
    cold.bags["ros2-mcap"] = [
        _result("get_message_at_time /odom", 80.0, answered=GB // 200),  # 0.5 % of the bag
        _result("analyze_trajectory", 160.0),  # over 1.5 x 100
        _result("get_image_at_time", 90.0),
    ]
    delayed = ColdPass("delayed", 20.0, bags={"ros2-mcap": [_result("get_message_at_time /odom", 310.0)]})
    quarter = ColdPass("quarter", 0.0, block_cache_bytes=GB // 4, peaks={"bag-store": (GB // 4 - 5, 0)})
    quarter.bags["ros2-mcap"] = [_result("bag_info", 9.0), _result("get_image_at_time", 50.0, differs="call 0: ...")]
    machine = Machine(2, "test cpu", 4.0, "3.11", "linux", "abc")
    run = RunResult(machine, False, 3, bags, floors, cold=[cold, delayed, quarter])
    page = render(run, notes="")
    rows = [line for line in page.splitlines() if line.startswith("| stack cold") or line.startswith("| bag 4x")]
    assert rows == [
        "| stack cold get_message_at_time /odom < 1x floor (open + decode 1 s of /odom) | ros2-mcap | 80.0 | 100 "
        "| met |",
        "| stack cold analyze_trajectory < 1.5x floor (open + decode all /odom) | ros2-mcap | 160 | 150 | **missed** |",
        "| stack cold get_image_at_time < 1.5x floor (open + decode 1 image) | ros2-mcap | 90.0 | 150 | met |",
        "| stack cold get_message_at_time /odom, 20 ms per S3 request < 300 ms | ros2-mcap | 310 | 300 | **missed** |",
        "| stack cold get_message_at_time /odom fetches < 1% of the bag (MB) | ros2-mcap | 10 (0.50%) | 20 | met |",
        "| bag 4x the block cache: every tool answers as in the cold pass, cache within its bound | ros2-mcap "
        "| 1 of 2 answers equal; blocks at most 500 MB | 500 MB | **missed** |",
    ]
    assert "| get_image_at_time | 50.0 | 5.0 | 0.00 | **differs**: call 0: ... |" in page
    assert "| bag-store | 500 | 500 | met | 0.00 |" in page
