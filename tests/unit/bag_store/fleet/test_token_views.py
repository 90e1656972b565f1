"""A token limited by its profile or allow/deny lists sees in answers across bags only what its tools would
show: the gateway passes the tools it may call, and each view needs one of the per-bag tools that reveal
the same data (a token that may not call analyze_logs or a raw message reader sees no logs)."""

from __future__ import annotations

import pytest
from mcp import Client
from mcp.server.subscriptions import InMemorySubscriptionBus

from bagmcp_gateway.access.policy import ToolPolicy
from bagmcp_gateway.mcp_front.aggregator import Gateway, gateway_server
from bagmcp_gateway.upstreams.connections import Connections
from bagmcp_gateway.upstreams.tool_catalog import ToolCatalog
from tests.checks.fleet_checks import query
from tests.fixtures.inprocess import InProcess
from tests.fixtures.mcp_client import call, call_error
from tests.unit.conftest import DRIVE_NAMES

pytestmark = pytest.mark.anyio
TRAJECTORY_ONLY = ("query_bags", "find_bags", "analyze_trajectory", "get_job", "cancel_job")


def _limited_gateway(served: InProcess, enabled: tuple[str, ...]) -> Client:
    upstreams = served.composition.upstreams
    links = Connections(upstreams)
    bus = InMemorySubscriptionBus()
    gateway = Gateway(ToolCatalog(upstreams, links, bus), links, policy=ToolPolicy(enabled=enabled))
    return Client(gateway_server(gateway, bus), cache=None)


async def test_a_token_limited_to_trajectories_reads_poses_but_not_logs_or_the_bag_list(
    served_drive: InProcess,
) -> None:
    async with _limited_gateway(served_drive, TRAJECTORY_ONLY) as client:
        speeds = await query(client, "SELECT bag, max(speed) FROM poses GROUP BY bag ORDER BY bag")
        assert [row[0] for row in speeds["rows"]] == sorted(DRIVE_NAMES)
        refused = await call_error(client, "query_bags", sql="SELECT count(*) FROM logs")
        assert "may not read the logs view" in refused
        assert "poses" in refused  # it says what the token may read
        assert "may not read the bags view" in await call_error(client, "query_bags", sql="SELECT * FROM bags")
        assert "logs" in await call_error(client, "find_bags", log_level="ERROR")
        found = await call(client, "find_bags", speed_above=0.4)
        assert found["result"]["total"] == len(DRIVE_NAMES)


async def test_a_token_without_query_bags_is_not_shown_it(served_drive: InProcess) -> None:
    async with _limited_gateway(served_drive, ("list_bags", "bag_info")) as client:
        names = [t.name for t in (await client.list_tools()).tools]
        assert "query_bags" not in names
        assert "not enabled" in await call_error(client, "query_bags", sql="SELECT 1")


async def test_an_unrestricted_caller_reads_every_view(served_drive: InProcess) -> None:
    async with Client(served_drive.gateway(), cache=None) as client:
        counted = await query(client, "SELECT (SELECT count(*) FROM logs), (SELECT count(*) FROM bags)")
        assert counted["rows"][0][1] == len(DRIVE_NAMES)
        assert counted["rows"][0][0] > 0
