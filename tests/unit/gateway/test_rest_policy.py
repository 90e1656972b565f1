"""The table of REST routes and the tools that give the same data: every tool it names is one the service
serving the route publishes (so a token that may call none of a service's tools reads none of its REST data),
plot artifacts are open to exactly the tools that make them, and a route the table does not name is closed to
a restricted token."""

from __future__ import annotations

from fnmatch import fnmatchcase

import pytest
from mcp import Client

from bagmcp_gateway.access.rest_policy import REST_ROUTES, rest_refusal, route_for
from tests.fixtures.inprocess import InProcess

pytestmark = pytest.mark.anyio
SERVED_BY = {"bags": "bag-store", "query": "bag-store", "artifacts": "plotting"}


async def _tool_names(served: InProcess, service: str) -> list[str]:
    async with Client(served.service(service), cache=None) as client:
        return [t.name for t in (await client.list_tools()).tools]


async def test_each_route_names_tools_of_the_service_that_serves_it(served_small: InProcess) -> None:
    for row in REST_ROUTES:
        if row.tools is None:
            continue
        segment = row.path.pattern.removeprefix("/api/v1/").split("/")[0]
        names = await _tool_names(served_small, SERVED_BY[segment])
        for glob in row.tools:
            assert any(fnmatchcase(n, glob) for n in names), (row.path.pattern, glob, SERVED_BY[segment])
    plotting = await _tool_names(served_small, "plotting")
    artifacts = route_for("GET", "/api/v1/artifacts/abc")
    assert artifacts is not None
    assert artifacts.tools is not None
    assert all(any(fnmatchcase(n, g) for g in artifacts.tools) for n in plotting)  # every tool that makes one


def test_a_route_is_open_when_one_of_its_tools_may_be_called() -> None:
    assert rest_refusal("GET", "/api/v1/bags", None) is None  # an unrestricted token
    assert rest_refusal("GET", "/api/v1/bags", ["find_bags"]) is None
    assert rest_refusal("GET", "/api/v1/bags/b1/download", ["get_messages_in_range"]) is None
    assert rest_refusal("GET", "/api/v1/artifacts/abc", ["plot_2d"]) is None
    refused = rest_refusal("GET", "/api/v1/bags/b1/download", ["bag_info", "plot_2d"])
    assert refused is not None
    assert "needs one of the tools get_messages_in_range, filter_bag" in refused
    assert rest_refusal("GET", "/api/v1/bags/b1", ["bag_info"]) is None


def test_scope_only_routes_ignore_the_tools_and_unknown_routes_are_closed_to_restricted_tokens() -> None:
    for method, path in [("POST", "/api/v1/bags"), ("DELETE", "/api/v1/bags/b1"), ("GET", "/api/v1/session")]:
        assert rest_refusal(method, path, []) is None
    assert rest_refusal("POST", "/api/v1/lab/runs", []) is None  # the Lab's calls are checked on /mcp
    assert rest_refusal("GET", "/api/v1/elsewhere", None) is None
    closed = rest_refusal("GET", "/api/v1/elsewhere", ["list_bags"])
    assert closed is not None
    assert "not open to this token" in closed
    assert rest_refusal("GET", "/metrics", []) is None  # outside /api/v1: the admin scope decides
