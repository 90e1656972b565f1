"""Hostile SQL through query_bags (in process, through the gateway): files, URLs, catalogs, extensions,
settings and second statements are refused before anything runs; a cross join of every pose with every pose
and a recursive CTE without end are stopped by the time limit, while other calls keep being answered."""

from __future__ import annotations

import time
from collections.abc import Iterator
from pathlib import Path

import anyio
import pytest
from mcp import Client

from bagmcp_bag_store.settings import QueryLimits
from tests.checks.fleet_checks import query
from tests.fixtures.bagfactory import BagKind
from tests.fixtures.inprocess import InProcess, copy_bags, in_process
from tests.fixtures.mcp_client import call, call_error

pytestmark = pytest.mark.anyio
TIMEOUT_S = 0.8  # long enough for the views to load on a busy machine; each stopped query waits it out
REFUSED = {
    "SELECT * FROM read_csv('/etc/passwd')": "read_csv() is not allowed",
    "SELECT * FROM '/etc/passwd'": "no table",
    "SELECT * FROM read_parquet('s3://bucket/fleet/v1/poses/x.parquet')": "read_parquet() is not allowed",
    "SELECT * FROM 'https://example.com/data.csv'": "no table",
    "SELECT * FROM glob('/root/*')": "glob() is not allowed",
    "SELECT * FROM query_table('poses')": "query_table() is not allowed",
    "ATTACH '/tmp/other.duckdb' AS other": "only SELECT",
    "COPY (SELECT * FROM poses) TO '/tmp/poses.csv'": "only SELECT",
    "INSTALL httpfs": "only SELECT",
    "LOAD httpfs": "only SELECT",
    "PRAGMA database_list": "only SELECT",
    "SET enable_external_access = true": "only SELECT",
    "SELECT 1; DROP TABLE poses": "exactly one",
    "SELECT * FROM other.main.poses": "not a view",
    "CREATE TABLE x AS SELECT * FROM poses": "only SELECT",
}


@pytest.fixture(scope="module")
def limited(drive_bags: dict[BagKind, Path], tmp_path_factory: pytest.TempPathFactory) -> Iterator[InProcess]:
    folder = copy_bags(list(drive_bags.values()), tmp_path_factory.mktemp("hostile") / "bags")
    limits = QueryLimits(timeout_s=TIMEOUT_S, memory_mb=512)
    with in_process(folder, tmp_path_factory.mktemp("data"), queries=limits, job_budget_s=30) as services:
        yield services


async def test_files_urls_catalogs_extensions_settings_and_second_statements_are_refused(limited: InProcess) -> None:
    async with Client(limited.gateway(), cache=None) as client:
        await query(client, "SELECT count(*) FROM poses")  # the views are loaded: refusals come from the check
        for sql, reason in REFUSED.items():
            text = await call_error(client, "query_bags", sql=sql)
            assert reason in text, (sql, text)


async def _stopped_while_others_answer(client: Client, sql: str) -> tuple[str, float]:
    """The error of ``sql`` and the slowest list_bags answered meanwhile."""
    slowest = 0.0
    error = ""

    async def hostile() -> None:
        nonlocal error
        error = await call_error(client, "query_bags", sql=sql)

    async with anyio.create_task_group() as group:
        group.start_soon(hostile)
        await anyio.sleep(0.2)
        while not error:
            began = time.monotonic()
            listed = await call(client, "list_bags")
            slowest = max(slowest, time.monotonic() - began)
            assert listed["total"] == 3
            await anyio.sleep(0.1)
    return error, slowest


async def test_a_cross_join_of_every_pose_is_stopped_at_the_time_limit_and_the_server_keeps_answering(
    limited: InProcess,
) -> None:
    async with Client(limited.gateway(), cache=None) as client:
        await query(client, "SELECT count(*) FROM poses")
        began = time.monotonic()
        sql = "SELECT count(*) FROM poses a, poses b, poses c WHERE a.x + b.y + c.speed > -1"
        error, slowest = await _stopped_while_others_answer(client, sql)
        assert f"time limit of {TIMEOUT_S:g} s" in error
        assert time.monotonic() - began < TIMEOUT_S + 5
        assert slowest < 1.0


async def test_a_recursive_cte_without_end_is_stopped(limited: InProcess) -> None:
    async with Client(limited.gateway(), cache=None) as client:
        sql = "WITH RECURSIVE r(n) AS (SELECT 1 UNION ALL SELECT n + 1 FROM r) SELECT max(n) FROM r"
        error, _ = await _stopped_while_others_answer(client, sql)
        assert "time limit" in error or "memory limit" in error
