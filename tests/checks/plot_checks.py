"""The plotting tools on the generated drive bags: real PNGs of the right size with something drawn, and
structured summaries that match the drive's known numbers."""

from __future__ import annotations

import base64
import io
from typing import Any

import pytest
from mcp import Client
from PIL import Image

from tests.checks.search_checks import finished
from tests.fixtures import drive_lidar as lidar
from tests.fixtures import drive_scenario as drive
from tests.fixtures.mcp_client import call_error, text_of

MIN_COLOURS = 8
MAX_PNG_BYTES = 200_000


async def plot(client: Client, tool: str, **arguments: object) -> tuple[dict[str, Any], Image.Image]:
    """The plot's summary and its decoded PNG (from the answer itself)."""
    answer = await client.call_tool(tool, arguments)
    assert not answer.is_error, text_of(answer)
    assert answer.structured_content is not None
    report = await finished(client, answer.structured_content, timeout_s=120)
    images = [c for c in answer.content if c.type == "image"]
    assert images, f"{tool} answered without an image"
    png = base64.b64decode(images[0].data)
    assert len(png) < MAX_PNG_BYTES
    assert any(c.type == "resource_link" and report["artifact"]["id"] in c.uri for c in answer.content)
    picture = Image.open(io.BytesIO(png))
    assert picture.format == "PNG"
    assert (picture.width, picture.height) == (report["artifact"]["width"], report["artifact"]["height"])
    assert len(picture.convert("RGB").getcolors(maxcolors=1 << 20) or []) >= MIN_COLOURS, f"{tool}: blank image"
    return report, picture


def _series(report: dict[str, Any]) -> dict[str, tuple[int, float, float]]:
    return {s["name"]: (s["points"], s["min"], s["max"]) for s in report["series"]}


async def check_plots(client: Client, bag: str, other: str) -> None:
    report, picture = await plot(
        client, "plot_timeseries", bag=bag, paths=["/cmd_vel.linear.x", "/odom.twist.twist.linear.x"]
    )
    shown = _series(report)
    assert shown["/cmd_vel.linear.x"] == pytest.approx((601, 0.0, drive.MAX_CMD_LINEAR_X_MPS))
    assert shown["/odom.twist.twist.linear.x"] == pytest.approx((1201, 0.0, drive.MAX_SPEED_MPS))
    assert (picture.width, picture.height) == (1000, 600)
    again, _ = await plot(client, "plot_timeseries", bag=bag, paths=["/cmd_vel.linear.x", "/odom.twist.twist.linear.x"])
    assert again["artifact"]["id"] == report["artifact"]["id"]  # the same request reuses the stored image
    window, _ = await plot(
        client, "plot_timeseries", bag=bag, paths=["/imu.angular_velocity.z"], start=10, end=20, style="step"
    )
    assert window["start"]["offset_s"] == pytest.approx(10.0)
    assert _series(window)["/imu.angular_velocity.z"][0] == 501
    path, _ = await plot(client, "plot_2d", bag=bag, color_by_time=True)
    xs, ys = _series(path)["/odom.pose.pose.position.x"], _series(path)["/odom.pose.pose.position.y"]
    assert (xs[1], xs[2]) == pytest.approx(drive.X_EXTENT_M, abs=1e-6)
    assert (ys[1], ys[2]) == pytest.approx(drive.Y_EXTENT_M, abs=1e-6)
    scan, _ = await plot(client, "plot_lidar_scan", bag=bag, time=lidar.CLOSEST_S, within=0.5)
    assert scan["series"][0]["min"] == pytest.approx(lidar.CLOSEST_RANGE_M, abs=1e-3)
    histogram, _ = await plot(client, "plot_histogram", bag=bag, path="/cmd_vel.linear.x", bins=20)
    assert _series(histogram)["/cmd_vel.linear.x"][0] == 601
    runs, _ = await plot(client, "compare_runs", bags=[bag, other], path="/odom.twist.twist.linear.x", align="motion")
    assert [s["points"] for s in runs["series"]] == [1201, 1201]
    assert len(runs["bags"]) == 2
    wrong = await call_error(client, "plot_timeseries", bag=bag, paths=["/odom.twist.twist.linear.w"])
    assert "valid paths" in wrong
    assert "twist.twist.linear.x" in wrong
    not_a_number = await call_error(client, "plot_histogram", bag=bag, path="/odom.header.frame_id")
    assert "not a number" in not_a_number
