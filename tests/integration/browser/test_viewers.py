"""The MCP Apps viewers in a real browser: each tool with a viewer is called over HTTP through the gateway
as an Apps host calls it, its viewer document is read through the gateway (resources/read), loaded in a
test host page that speaks the Apps messages, and what it draws is checked against the scenario bag's
known values (tests/fixtures/scenario.py), with no browser console error and no serious axe finding."""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import pytest
from playwright.sync_api import Frame

from tests.fixtures import scenario as sc
from tests.integration.browser.apps_client import call_tool, rpc
from tests.integration.browser.apps_host import open_viewer
from tests.integration.browser.harness import Watched, axe_violations, drawn, screenshot
from tests.integration.stack import TOKEN, Stack

pytestmark = [pytest.mark.integration, pytest.mark.browser]
APP_MIME = "text/html;profile=mcp-app"
VIEW = "bagmcp/view"
Check = Callable[[list[dict[str, Any]], Frame], None]


@pytest.fixture(scope="module")
def bag(uploaded: dict[str, dict[str, Any]]) -> str:
    return str(uploaded["ros1"]["name"])


@pytest.fixture(scope="module")
def tools(stack: Stack) -> dict[str, dict[str, Any]]:
    """tools/list as an Apps host sees it."""
    return {t["name"]: t for t in rpc(stack.url, TOKEN, "tools/list", {})["tools"]}


def viewer_of(stack: Stack, tool: dict[str, Any]) -> str:
    uri = tool["_meta"]["ui"]["resourceUri"]
    (content,) = rpc(stack.url, TOKEN, "resources/read", {"uri": uri})["contents"]
    assert content["mimeType"] == APP_MIME
    return str(content["text"])


def test_apps_clients_see_viewers_and_other_clients_get_the_answers_they_always_had(
    stack: Stack, tools: dict[str, dict[str, Any]], bag: str
) -> None:
    with_viewer = {n for n, t in tools.items() if "ui" in t.get("_meta", {})}
    assert with_viewer == {
        "plot_timeseries", "plot_2d", "plot_lidar_scan", "plot_histogram", "compare_runs",
        "analyze_trajectory", "analyze_lidar_scan",
    }  # fmt: skip
    assert tools["plot_2d"]["_meta"]["ui"]["resourceUri"] == "ui://plotting/viewer.html"
    assert tools["analyze_trajectory"]["_meta"]["ui"]["resourceUri"] == "ui://analysis/viewer.html"
    plain = {t["name"]: t for t in rpc(stack.url, TOKEN, "tools/list", {}, apps=False)["tools"]}
    assert not any("ui" in t.get("_meta", {}) for t in plain.values())
    arguments = {"bag": bag, "paths": ["/cmd_vel.linear.x"]}
    seen, shown = (call_tool(stack.url, TOKEN, "plot_timeseries", arguments, apps=a) for a in (False, True))
    assert VIEW not in seen.get("_meta", {})
    assert VIEW in shown["_meta"]
    assert seen["content"] == shown["content"]  # the same text, PNG and link
    assert seen["structuredContent"] == shown["structuredContent"]
    listed = {r["uri"] for r in rpc(stack.url, TOKEN, "resources/list", {})["resources"]}
    assert {"ui://plotting/viewer.html", "ui://analysis/viewer.html"} <= listed


def _close(a: float | None, b: float, tolerance: float = 1e-6) -> bool:
    return a is not None and math.isclose(a, b, abs_tol=tolerance)


def timeseries_matches_the_commands(views: list[dict[str, Any]], frame: Frame) -> None:
    (view,) = views
    times, values = view["data"][0], view["data"][1]
    assert len(times) == sc.COUNTS[sc.CMD_TOPIC]
    assert all(_close(v, sc.cmd_speed_at(t)) for t, v in zip(times, values, strict=True))
    legend = frame.locator(".u-legend").inner_text()
    assert "/cmd_vel.linear.x [m/s]" in legend


def path_matches_the_circle(views: list[dict[str, Any]], frame: Frame) -> None:
    (view,) = views
    assert len(view["x"]) == sc.COUNTS[sc.ODOM_TOPIC]
    for x, y, t in zip(view["x"], view["y"], view["t"], strict=True):
        want_x, want_y, _ = sc.pose_at(t)
        assert _close(x, want_x, 1e-4), (t, x)
        assert _close(y, want_y, 1e-4), (t, y)
    frame.locator("input[type=range]").fill("0")
    assert frame.locator("output").inner_text().startswith("0.00 s: x 0, y 0")


def scan_shows_the_obstacle(views: list[dict[str, Any]], frame: Frame) -> None:
    (view,) = views
    assert view["scans"] >= 1
    assert min(p["r"] for p in view["points"]) == pytest.approx(sc.OBSTACLE_RANGE_M)


def scans_follow_the_obstacle_across_the_slider(views: list[dict[str, Any]], frame: Frame) -> None:
    (view,) = views
    slider = frame.locator("input[type=range]")
    assert view["scans"] >= 10
    for index in (0, view["scans"] - 1):
        slider.fill(str(index))
        now = drawn(frame)[0]
        assert now["index"] == index
        when = float(frame.locator("output").inner_text().split(" at ")[1].split(" s")[0])
        assert min(p["r"] for p in now["points"]) == pytest.approx(sc.scan_min_at(when), abs=1e-6)


def histogram_counts_every_command(views: list[dict[str, Any]], frame: Frame) -> None:
    (view,) = views
    assert sum(view["counts"]) == sc.COUNTS[sc.CMD_TOPIC]
    assert view["edges"][0] == pytest.approx(0.5)
    assert view["edges"][-1] == pytest.approx(sc.cmd_speed_at(9))


def runs_overlay_the_same_commands(views: list[dict[str, Any]], frame: Frame) -> None:
    (view,) = views
    assert len(view["names"]) == 2
    times = view["data"][0]
    for column in view["data"][1:]:
        assert all(v is None or _close(v, sc.cmd_speed_at(t)) for t, v in zip(times, column, strict=True))
        assert sum(v is not None for v in column) == sc.COUNTS[sc.CMD_TOPIC]


CMD = "/cmd_vel.linear.x"
CASES: dict[str, tuple[str, Callable[[str, str], dict[str, Any]], Check]] = {
    "timeseries": ("plot_timeseries", lambda b, o: {"bag": b, "paths": [CMD]}, timeseries_matches_the_commands),
    "xy": ("plot_2d", lambda b, o: {"bag": b, "topic": "/odom"}, path_matches_the_circle),
    "scan": ("plot_lidar_scan", lambda b, o: {"bag": b, "time": 7.0, "within": 0.5}, scan_shows_the_obstacle),
    "histogram": ("plot_histogram", lambda b, o: {"bag": b, "path": CMD}, histogram_counts_every_command),
    "compare": ("compare_runs", lambda b, o: {"bags": [b, o], "path": CMD}, runs_overlay_the_same_commands),
    "trajectory": ("analyze_trajectory", lambda b, o: {"bag": b, "topic": "/odom"}, path_matches_the_circle),
    "scans": (
        "analyze_lidar_scan",
        lambda b, o: {"bag": b, "within": 0.5},
        scans_follow_the_obstacle_across_the_slider,
    ),
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_each_viewer_draws_a_real_tool_result_in_a_host_page(
    case: str,
    stack: Stack,
    tools: dict[str, dict[str, Any]],
    bag: str,
    uploaded: dict[str, dict[str, Any]],
    watched: Watched,
) -> None:
    tool, arguments_of, check = CASES[case]
    arguments = arguments_of(bag, str(uploaded["ros2-mcap"]["name"]))
    result = call_tool(stack.url, TOKEN, tool, arguments)
    assert VIEW in result["_meta"], result
    frame = open_viewer(watched.page, viewer_of(stack, tools[tool]), arguments, result)
    assert frame.locator(".bv-error").count() == 0, frame.locator(".bv-error").inner_text()
    check(drawn(frame), frame)
    messages = [m.get("method") for m in watched.page.evaluate("window.hostLog")]
    assert messages[:2] == ["ui/initialize", "ui/notifications/initialized"]
    assert "ui/notifications/size-changed" in messages
    assert axe_violations(frame) == []
    screenshot(watched.page, f"viewer-{case}")
