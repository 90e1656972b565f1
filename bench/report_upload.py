"""The page's parts for the stack's uploads (bench/uploads.py): upload to ready against the rosbags
full-decode floor, and the caches on disk against their bounds (both issue 21)."""

from __future__ import annotations

from collections.abc import Iterator

from bench.floors import FULL_DECODE
from bench.report_cold import mb
from bench.report_parts import FLOOR_LABELS, table, yes
from bench.results import RunResult
from bench.stats import Timing
from bench.uploads import CacheUse, UploadTiming

UPLOAD_FLOOR_FACTOR = 3.0


def seconds(value: float) -> str:
    return f"{value:,.2f}" if value < 10 else f"{value:,.1f}"


def _floor(run: RunResult, kind: str) -> Timing | None:
    return run.floors.get(kind, {}).get(FULL_DECODE)


def upload_limit_s(floor: Timing) -> float:
    return UPLOAD_FLOOR_FACTOR * floor.median_ms / 1000


def target_rows(run: RunResult) -> list[list[str]]:
    """Each format's upload to ready against 3x its full-decode floor, and each moment's caches against
    their bounds, as rows of the issue 21 table (target, format, figure, limit, met)."""
    rows = []
    what = f"stack upload to ready < {UPLOAD_FLOOR_FACTOR:g}x floor ({FLOOR_LABELS[FULL_DECODE]})"
    for upload in run.uploads:
        floor = _floor(run, upload.kind)
        if floor is None:
            continue
        limit = upload_limit_s(floor)
        ratio = upload.ready_s / (floor.median_ms / 1000)
        figure = f"{seconds(upload.ready_s)} s ({upload.mb_per_s:,.0f} MB/s, {ratio:.2f}x)"
        rows.append([what, upload.kind, figure, f"{seconds(limit)} s", yes(upload.ready_s < limit)])
    for when, uses in run.caches:
        held = sum(u.blocks + u.other for u in uses)
        bound = sum(u.blocks_bound + u.other_bound for u in uses)
        figure = f"{mb(held)} MB in {len(uses)} processes"
        met = all(u.within for u in uses)
        rows.append([f"stack caches on disk within their bounds, {when}", "all", figure, f"{mb(bound)} MB", yes(met)])
    return rows


def sections(run: RunResult) -> Iterator[str]:
    """The uploads' table and each moment's caches per process."""
    if run.uploads:
        yield from _uploads(run, run.uploads)
    if run.caches:
        yield "## stack, caches on disk"
        yield ""
        yield (
            "Each service's and worker's `$BAGMCP_DATA_DIR/cache` measured on disk: *blocks* is the block cache "
            "(bound `BAGMCP_BLOCK_CACHE_BYTES`), the rest whole copies of bags and local indexes (bound "
            "`BAGMCP_CACHE_MAX_BYTES`); the bounds are those the stack's processes were started with."
        )
        yield ""
    for when, uses in run.caches:
        yield from _caches(when, uses)


def _uploads(run: RunResult, uploads: list[UploadTiming]) -> Iterator[str]:
    yield "## stack, upload to ready"
    yield ""
    yield (
        "Each benchmark bag uploaded with `bagmcp upload` through the gateway, timed from the command's start "
        f"until `GET /api/v1/bags/<id>` answers `ready` (read every 0.1 s), one bag after the other: *sent* is "
        "when the command returned (body received, stored in S3, ingest queued); *ingest* the bag-store "
        "worker's own time in the ingest task (its Celery log). The floor is rosbags opening the file and "
        f"decoding every message, median of the floor runs ({FLOOR_LABELS[FULL_DECODE]} in the floors table)."
    )
    yield ""
    rows = []
    for upload in uploads:
        floor = _floor(run, upload.kind)
        limit = upload_limit_s(floor) if floor else None
        rows.append(
            [
                upload.kind,
                mb(upload.size_bytes),
                seconds(upload.sent_s),
                seconds(upload.ready_s),
                f"{upload.mb_per_s:,.0f}",
                seconds(upload.ingest_s) if upload.ingest_s is not None else "",
                seconds(floor.median_ms / 1000) if floor else "",
                f"{upload.ready_s / (floor.median_ms / 1000):.2f}" if floor else "",
                yes(upload.ready_s < limit) if limit is not None else "",
            ]
        )
    within = f"< {UPLOAD_FLOOR_FACTOR:g}x"
    header = ["format", "MB", "sent s", "ready s", "MB/s", "ingest s", "floor s", "ready vs floor", within]
    yield from table(header, rows)


def _caches(when: str, uses: list[CacheUse]) -> Iterator[str]:
    yield f"### {when} (MB)"
    yield ""
    rows = [[u.process, mb(u.blocks), mb(u.blocks_bound), mb(u.other), mb(u.other_bound), yes(u.within)] for u in uses]
    total = [sum(u.blocks for u in uses), sum(u.blocks_bound for u in uses)]
    other = [sum(u.other for u in uses), sum(u.other_bound for u in uses)]
    rows.append(["together", *(mb(x) for x in (*total, *other)), yes(all(u.within for u in uses))])
    header = ["process", "blocks", "block bound", "whole copies and indexes", "copy bound", ""]
    yield from table(header, rows)
