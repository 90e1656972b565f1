"""MCP Apps through the gateway: viewers exposed under an upstream's prefix keep the ui:// scheme hosts need,
tools point at the exposed URI, and a client without Apps gets the listing and answers it always had
while the service's own answer carries the view data (checked against the scenario's numbers)."""

from __future__ import annotations

from typing import Any

import mcp.types as types
import pytest
from mcp import Client
from mcp.client.extension import advertise

from bagmcp_gateway.upstreams.upstream import Upstream
from bagmcp_kit.web.viewers import VIEW_META_KEY, without_view_data, without_viewer
from tests.fixtures import scenario as sc
from tests.fixtures.inprocess import InProcess

pytestmark = pytest.mark.anyio
APP_MIME = "text/html;profile=mcp-app"
APPS = [advertise("io.modelcontextprotocol/ui", {"mimeTypes": [APP_MIME]})]


def _upstream(prefix: str | None) -> Upstream:
    return Upstream(name="plotting", url="http://plotting:8000/mcp", prefix=prefix)


def test_a_prefixed_viewer_keeps_the_ui_scheme_and_maps_back() -> None:
    up = _upstream("p2")
    assert up.exposed_uri("ui://plotting/viewer.html") == "ui://p2.plotting/viewer.html"
    assert up.original_uri("ui://p2.plotting/viewer.html") == "ui://plotting/viewer.html"
    assert up.exposed_uri("bagmcp://artifacts/x") == "p2+bagmcp://artifacts/x"
    assert up.original_uri("p2+bagmcp://artifacts/x") == "bagmcp://artifacts/x"
    assert up.original_uri("ui://plotting/viewer.html") is None
    assert _upstream(None).exposed_uri("ui://plotting/viewer.html") == "ui://plotting/viewer.html"


def test_a_tool_points_at_its_viewer_under_the_exposed_uri() -> None:
    tool = types.Tool(
        name="plot_2d", input_schema={"type": "object"}, _meta={"ui": {"resourceUri": "ui://plotting/viewer.html"}}
    )
    exposed = _upstream("p2").exposed_tool(tool)
    assert exposed.name == "p2__plot_2d"
    assert exposed.meta == {"ui": {"resourceUri": "ui://p2.plotting/viewer.html"}}
    assert _upstream(None).exposed_tool(tool).meta == tool.meta
    assert without_viewer(tool).meta is None


def test_view_data_is_dropped_and_everything_else_kept() -> None:
    result: dict[str, Any] = {"content": [], "_meta": {VIEW_META_KEY: {"kind": "xy"}, "other": 1}}
    assert without_view_data(result) == {"content": [], "_meta": {"other": 1}}
    assert without_view_data({"content": [], "_meta": {VIEW_META_KEY: {}}}) == {"content": []}
    assert without_view_data({"content": []}) == {"content": []}


async def test_a_client_without_apps_sees_no_viewer_and_no_view_data(served: InProcess) -> None:
    async with Client(served.gateway(), cache=None) as client:
        capabilities = client.session.server_capabilities
        assert capabilities is not None
        assert "io.modelcontextprotocol/ui" in (capabilities.extensions or {})
        tools = (await client.list_tools()).tools
        assert all(not (t.meta or {}).get("ui") for t in tools)
        answer = await client.call_tool("plot_timeseries", {"bag": "scenario", "paths": ["/cmd_vel.linear.x"]})
        assert not answer.is_error
        assert VIEW_META_KEY not in (answer.meta or {})
        assert [c.type for c in answer.content] == ["text", "image", "resource_link"]
        viewer = await client.read_resource("ui://plotting/viewer.html")
        (content,) = viewer.contents
        assert content.mime_type == APP_MIME
        assert isinstance(content, types.TextResourceContents)
        assert "ui/initialize" in content.text


async def test_an_apps_client_gets_the_numbers_the_viewer_draws_through_the_gateway(served: InProcess) -> None:
    async with Client(served.gateway(), cache=None, extensions=APPS) as client:
        listed = {t.name: t for t in (await client.list_tools()).tools}
        assert (listed["plot_timeseries"].meta or {})["ui"] == {"resourceUri": "ui://plotting/viewer.html"}
        assert (listed["analyze_trajectory"].meta or {})["ui"] == {"resourceUri": "ui://analysis/viewer.html"}
        assert "ui" not in (listed["bag_info"].meta or {})
        answer = await client.call_tool("plot_timeseries", {"bag": "scenario", "paths": ["/cmd_vel.linear.x"]})
    view = (answer.meta or {})[VIEW_META_KEY]
    (series,) = view["series"]
    assert view["kind"] == "timeseries"
    assert series["name"] == "/cmd_vel.linear.x"
    assert series["unit"] == "m/s"
    assert len(series["t"]) == sc.COUNTS[sc.CMD_TOPIC]
    assert series["v"] == pytest.approx([sc.cmd_speed_at(t) for t in series["t"]])


async def test_a_service_adds_views_only_for_callers_that_draw_them(served: InProcess) -> None:
    arguments = {"bag": "scenario", "topic": "/odom"}
    async with Client(served.service("analysis"), cache=None) as client:
        plain = await client.call_tool("analyze_trajectory", arguments)
    assert not plain.is_error
    assert VIEW_META_KEY not in (plain.meta or {})  # nothing read again for a client that does not draw it


async def test_a_trajectory_answer_carries_the_path_and_a_scan_answer_the_scans(served: InProcess) -> None:
    async with Client(served.service("analysis"), cache=None, extensions=APPS) as client:
        path = await client.call_tool("analyze_trajectory", {"bag": "scenario", "topic": "/odom"})
        scans = await client.call_tool("analyze_lidar_scan", {"bag": "scenario", "within": 0.5})
    trajectory = (path.meta or {})[VIEW_META_KEY]
    assert trajectory["kind"] == "trajectory"
    assert len(trajectory["x"]) == sc.COUNTS[sc.ODOM_TOPIC]
    for x, y, t in zip(trajectory["x"], trajectory["y"], trajectory["t"], strict=True):
        assert (x, y) == pytest.approx(sc.pose_at(t)[:2], abs=1e-4)
    scan_view = (scans.meta or {})[VIEW_META_KEY]
    assert scan_view["kind"] == "scan"
    assert 10 <= len(scan_view["scans"]) <= 61
    for scan in scan_view["scans"]:
        assert len(scan["ranges"]) == sc.SCAN_BEAMS
        assert min(r for r in scan["ranges"] if r is not None) == pytest.approx(sc.scan_min_at(scan["t"]))
