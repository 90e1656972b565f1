"""The page's parts for the stack's cold passes (bench/cold.py): the issue 21 targets per format, and the
tables of each pass."""

from __future__ import annotations

from collections.abc import Iterator

from bench.cold import NOT_COMPARED, ColdPass, ColdResult
from bench.report_parts import FLOOR_LABELS, ms, table, yes
from bench.results import RunResult
from bench.stats import Timing

POINT = "get_message_at_time /odom"
COLD_FLOORS = {POINT: 1.0, "analyze_trajectory": 1.5, "plot_timeseries 2 odometry paths": 1.5, "get_image_at_time": 1.5}
DELAYED_POINT_MS = 300.0
POINT_SHARE = 0.01  # of the bag's bytes
MAX_LINES = 40


def _pass(run: RunResult, key: str) -> ColdPass | None:
    return next((p for p in run.cold if p.key == key), None)


def _result(found: ColdPass | None, kind: str, label: str) -> ColdResult | None:
    results = found.bags.get(kind, []) if found else []
    return next((r for r in results if r.call.label == label), None)


def _floor(run: RunResult, kind: str, result: ColdResult) -> Timing | None:
    key = result.call.floor
    return run.floors.get(kind, {}).get(key) if key else None


def _size(run: RunResult, kind: str) -> int:
    return next(b.size_bytes for b in run.bags if b.kind == kind)


def mb(count: int) -> str:
    return f"{count / 1e6:,.2f}" if count < 10e6 else f"{count / 1e6:,.0f}"


def target_rows(run: RunResult) -> list[list[str]]:
    """Each issue 21 target in each format: the figure, its limit, met or missed."""
    cold, delayed, quarter = _pass(run, "cold"), _pass(run, "delayed"), _pass(run, "quarter")
    rows = []
    for kind in [b.kind for b in run.bags]:
        for label, factor in COLD_FLOORS.items():
            result = _result(cold, kind, label)
            floor = _floor(run, kind, result) if result else None
            if result and floor:
                limit = factor * floor.median_ms
                what = f"stack cold {label} < {factor:g}x floor ({FLOOR_LABELS[result.call.floor or '']})"
                rows.append([what, kind, ms(result.cold.median_ms), ms(limit), yes(result.cold.median_ms < limit)])
        result = _result(delayed, kind, POINT)
        if result:
            value = result.cold.median_ms
            what = f"stack cold {POINT}, 20 ms per S3 request < {DELAYED_POINT_MS:g} ms"
            rows.append([what, kind, ms(value), ms(DELAYED_POINT_MS), yes(value < DELAYED_POINT_MS)])
        result = _result(cold, kind, POINT)
        if result:
            share, limit = result.cold_s3.answered_bytes / _size(run, kind), POINT_SHARE * _size(run, kind)
            what = f"stack cold {POINT} fetches < {POINT_SHARE:.0%} of the bag (MB)"
            rows.append(
                [
                    what,
                    kind,
                    f"{mb(result.cold_s3.answered_bytes)} ({share:.2%})",
                    mb(int(limit)),
                    yes(share < POINT_SHARE),
                ]
            )
        if quarter and kind in quarter.bags:
            rows.append(_quarter_row(quarter, kind))
    return rows


def _quarter_row(quarter: ColdPass, kind: str) -> list[str]:
    results = [r for r in quarter.bags[kind] if r.call.tool not in NOT_COMPARED]
    differ = [r.call.label for r in results if r.differs]
    bound = quarter.block_cache_bytes or 0
    peak = max((blocks for blocks, _ in quarter.peaks.values()), default=0)
    value = f"{len(results) - len(differ)} of {len(results)} answers equal; blocks at most {mb(peak)} MB"
    met = not differ and peak <= bound and quarter.error is None
    return [
        "bag 4x the block cache: every tool answers as in the cold pass, cache within its bound",
        kind,
        value,
        f"{mb(bound)} MB",
        yes(met),
    ]


def sections(run: RunResult) -> Iterator[str]:
    """The cold passes' tables."""
    if not run.cold:
        return
    yield "## stack, cold reads from S3"
    yield ""
    yield (
        "Before each tool's cold call the services (bag-store, analysis, plotting) and their workers are stopped "
        "and started again on the same ports with new, empty data directories, so no block cache, whole copy, "
        "local index or opened bag is left; Redis, weed and the gateway keep running. The tool is then called once "
        "on a six-second warm-up bag of the same format (imports, decoders, the gateway's session to the new "
        "process), and the timed cold call on the benchmark bag follows, then the warm calls. Every S3 request "
        "of every process goes through a loopback proxy started by the bench (bench/delay_proxy.py), which counts "
        "the bytes S3 answered (*S3 bytes*: block-cache ranges, whole copies, index files, HEADs, the workers' "
        "reads); *block-cache bytes* are the services' own `bagmcp_s3_fetched_bytes_total` (/metrics, the "
        "process label service, before and after the call; their workers' sums are not in it)."
    )
    yield ""
    for found in run.cold:
        yield from _pass_section(run, found)


def _pass_section(run: RunResult, found: ColdPass) -> Iterator[str]:
    titles = {
        "cold": "cold, S3 on loopback",
        "delayed": "cold, 20 ms added to every S3 request",
        "quarter": f"one stack with a block cache of {mb(found.block_cache_bytes or 0)} MB (a quarter of the bag)",
    }
    yield f"### {titles.get(found.key, found.key)}"
    yield ""
    if found.error:
        yield f"**Not measured to the end**: {found.error}"
        yield ""
    if found.key == "quarter":
        yield from _quarter_section(run, found)
        return
    header = [
        "call",
        "cold ms",
        "warm median ms",
        "S3 bytes cold (MB)",
        "block-cache bytes (MB)",
        "S3 requests",
        "% of bag",
        "warm S3 bytes",
        "floor ms",
        "cold vs floor",
    ]
    for kind, results in found.bags.items():
        yield f"#### {found.key}, {kind}"
        yield ""
        rows = []
        for r in results:
            floor = _floor(run, kind, r)
            rows.append(
                [
                    r.call.label,
                    ms(r.cold.median_ms),
                    ms(r.warm.median_ms) if len(r.warm) else "",
                    mb(r.cold_s3.answered_bytes),
                    mb(r.cold_fetched),
                    str(r.cold_s3.requests),
                    f"{r.cold_s3.answered_bytes / _size(run, kind):.2%}",
                    f"{r.warm_s3.answered_bytes:,}",
                    ms(floor.median_ms) if floor else "",
                    f"{r.cold.median_ms / floor.median_ms:.2f}" if floor else "",
                ]
            )
        yield from table(header, rows)
        yield from _requests(run, kind, _result(found, kind, POINT))


def _requests(run: RunResult, kind: str, point: ColdResult | None) -> Iterator[str]:
    """What the cold point read asked of S3, in order (paths without the bucket, ids shortened)."""
    if point is None or not point.cold_lines:
        return
    shown = [_short(line) for line in point.cold_lines[:MAX_LINES]]
    more = f" and {len(point.cold_lines) - MAX_LINES} more" if len(point.cold_lines) > MAX_LINES else ""
    yield f"The cold {POINT}'s {point.cold_s3.requests} requests to S3, in order{more}: " + "; ".join(
        f"`{line}`" for line in shown
    )
    yield ""


def _short(line: str) -> str:
    method, _, rest = line.partition(" ")
    path, _, ranged = rest.partition(" ")
    parts = path.strip("/").split("/")[1:]  # the bucket left out
    parts = [p[:8] + "…" if len(p) > 20 else p for p in parts]
    return " ".join(x for x in (method, "/".join(parts), ranged) if x)


def _answers(result: ColdResult) -> str:
    if result.call.tool in NOT_COMPARED:
        return "not compared (it lists every bag, and the passes add filter_bag's outputs)"
    return "equal" if result.differs is None else f"**differs**: {result.differs[:160]}"


def _quarter_section(run: RunResult, found: ColdPass) -> Iterator[str]:
    yield (
        "The services and workers started once with `BAGMCP_BLOCK_CACHE_BYTES` and `BAGMCP_CACHE_MAX_BYTES` at "
        "the bound, then every tool of every format in turn (first call, then warm calls with the cold pass's "
        "arguments); each answer is compared with the cold pass's for the same arguments (job ids, links and "
        "timings left out), and each process's cache directory is measured on disk every 0.1 s."
    )
    yield ""
    for kind, results in found.bags.items():
        yield f"#### quarter cache, {kind}"
        yield ""
        rows = [
            [
                r.call.label,
                ms(r.cold.median_ms),
                ms(r.warm.median_ms) if len(r.warm) else "",
                mb(r.cold_s3.answered_bytes + r.warm_s3.answered_bytes),
                _answers(r),
            ]
            for r in results
        ]
        yield from table(["call", "first ms", "warm median ms", "S3 bytes, all calls (MB)", "answers"], rows)
    bound = found.block_cache_bytes or 0
    rows = [
        [name, mb(blocks), mb(bound), yes(blocks <= bound), mb(other)]
        for name, (blocks, other) in sorted(found.peaks.items())
    ]
    yield "Most each process's cache held on disk (MB):"
    yield ""
    yield from table(["process", "blocks", "bound", "", "whole copies and indexes"], rows)
