"""query_bags and find_bags in process over the drive bags in three formats, checked against the per-bag
tools; the views resource; refusals that name what to do."""

from __future__ import annotations

import json

import pytest
from mcp import Client

from bagmcp_bag_store.fleet.views import VIEWS
from bagmcp_bag_store.settings import DEFAULT_QUERY_LIMITS
from tests.checks.fleet_checks import check_fleet, check_refusals, query
from tests.fixtures.drive_bags import expected_topic_counts
from tests.fixtures.inprocess import InProcess
from tests.unit.conftest import DRIVE_NAMES

pytestmark = pytest.mark.anyio


async def test_query_and_find_agree_with_the_per_bag_tools_on_three_formats(served_drive: InProcess) -> None:
    async with Client(served_drive.gateway(), cache=None) as client:
        await check_fleet(client, DRIVE_NAMES)


async def test_wrong_tables_columns_and_statements_are_refused_with_what_to_do(served_drive: InProcess) -> None:
    async with Client(served_drive.gateway(), cache=None) as client:
        await check_refusals(client)


async def test_the_bags_view_lists_every_ready_bag_with_its_summary(served_drive: InProcess) -> None:
    async with Client(served_drive.gateway(), cache=None) as client:
        answer = await query(client, "SELECT bag, format, duration_s, message_count FROM bags ORDER BY bag")
    assert [row[0] for row in answer["rows"]] == sorted(DRIVE_NAMES)
    assert {row[1] for row in answer["rows"]} == {"ros1", "ros2-sqlite3", "ros2-mcap"}
    assert all(abs(row[2] - 60.0) < 1e-6 for row in answer["rows"])
    assert answer["total_rows"] == 3
    assert not answer["truncated"]


async def test_the_views_resource_gives_every_view_with_its_columns_and_types(served_drive: InProcess) -> None:
    async with Client(served_drive.gateway(), cache=None) as client:
        listed = {str(r.uri) for r in (await client.list_resources()).resources}
        assert "bagmcp://fleet/views" in listed
        read = await client.read_resource("bagmcp://fleet/views")
    text = "\n".join(getattr(c, "text", "") for c in read.contents)
    for view in VIEWS.values():
        assert f"{view.name}: {view.doc}" in text
        for column in view.columns:
            assert f"  {column.name} {column.type}" in text


async def test_answers_past_the_row_limit_or_the_byte_budget_are_cut_and_say_so_with_the_total(
    served_drive: InProcess,
) -> None:
    poses = expected_topic_counts("ros1")["/odom"] * len(DRIVE_NAMES)
    budget = served_drive.composition.embedded.resources.max_result_bytes
    ordered = "FROM poses ORDER BY bag, t"
    async with Client(served_drive.gateway(), cache=None) as client:
        narrow = await query(client, f"SELECT bag, t {ordered}")
        exact = await query(client, f"SELECT bag, t {ordered} LIMIT {DEFAULT_QUERY_LIMITS.max_rows}")
        wide = await query(client, f"SELECT * {ordered}")
        following = await query(client, f"SELECT * {ordered} LIMIT 1 OFFSET {len(wide['rows'])}")
    limit = DEFAULT_QUERY_LIMITS.max_rows
    assert (narrow["total_rows"], len(narrow["rows"]), narrow["truncated"]) == (poses, limit, True)
    assert narrow["rows"] == exact["rows"]  # the first rows, in the query's order
    assert [row[0] for row in narrow["rows"]] == ["drive"] * limit
    assert (exact["total_rows"], exact["truncated"]) == (limit, False)
    assert wide["total_rows"] == poses
    assert wide["truncated"]
    assert 0 < len(wide["rows"]) < limit  # the byte budget cut it first
    used = sum(len(json.dumps(row, separators=(",", ":"))) + 1 for row in wide["rows"])
    more = len(json.dumps(following["rows"][0], separators=(",", ":"))) + 1
    assert used <= budget < used + more
