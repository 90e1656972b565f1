"""query_bags and find_bags in process over the drive bags in three formats, checked against the per-bag
tools; the views resource; refusals that name what to do."""

from __future__ import annotations

import pytest
from mcp import Client

from bagmcp_bag_store.fleet.views import VIEWS
from tests.checks.fleet_checks import check_fleet, check_refusals, query
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
