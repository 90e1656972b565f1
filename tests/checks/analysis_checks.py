"""The analysis tools on the generated drive bags (tests/fixtures/drive_*), against closed-form geometry.

Every way of serving runs these with the names its three drive bags got."""

from __future__ import annotations

import base64
import io
import math
from typing import Any

import pytest
from mcp import Client
from PIL import Image

from tests.checks.search_checks import finished
from tests.fixtures import drive_images as images
from tests.fixtures import drive_lidar as lidar
from tests.fixtures import drive_logs as logs
from tests.fixtures import drive_scenario as drive
from tests.fixtures import drive_sensors as sensors
from tests.fixtures import drive_tf as tf
from tests.fixtures.mcp_client import call, call_error

Answer = dict[str, Any]


async def result(client: Client, tool: str, **arguments: object) -> Answer:
    return await finished(client, await call(client, tool, **arguments), timeout_s=120)


async def check_trajectory(client: Client, bag: str) -> None:
    path = await result(client, "analyze_trajectory", bag=bag)
    assert (path["topic"], path["type"], path["clock"]) == ("/odom", "nav_msgs/msg/Odometry", "header")
    assert path["distance_2d_m"] == pytest.approx(drive.TOTAL_DISTANCE_M, rel=0.01)
    assert path["displacement_2d_m"] == pytest.approx(drive.DISPLACEMENT_M, abs=1e-6)
    assert path["duration_s"] == pytest.approx(drive.PATH_DURATION_S, abs=1e-6)
    assert path["max_speed_mps"] == pytest.approx(drive.MAX_SPEED_MPS, rel=0.02)
    assert path["moving_s"] == pytest.approx(drive.MOVING_TIME_S, abs=1.0)
    assert path["stopped_s"] == pytest.approx(drive.STOPPED_TIME_S, abs=1.0)
    assert len(path["stops"]) == len(drive.STOPS_S)
    extents = path["extents"]
    assert (extents["min_x"], extents["max_x"]) == pytest.approx(drive.X_EXTENT_M, abs=1e-6)
    assert (extents["min_y"], extents["max_y"]) == pytest.approx(drive.Y_EXTENT_M, abs=1e-6)
    end = path["end_pose"]
    assert (end["x"], end["y"], math.radians(end["yaw_deg"])) == pytest.approx(drive.END_POSE, abs=1e-6)
    corners = {(round(w["x"], 3), round(w["y"], 3)) for w in path["waypoints"] if w["reason"] != "start"}
    assert {(c.x_m, c.y_m) for c in drive.CORNERS} <= corners
    gps = await result(client, "analyze_trajectory", bag=bag, topic="/gps/fix")
    assert gps["distance_2d_m"] == pytest.approx(sensors.GPS_DISTANCE_M, rel=0.01)
    window = await result(client, "analyze_trajectory", bag=bag, start=1, end=5)
    assert window["distance_2d_m"] == pytest.approx(2.0, rel=0.01)


async def check_lidar(client: Client, bag: str) -> None:
    first = await result(client, "analyze_lidar_scan", bag=bag, within=lidar.NEAR_RANGE_M)
    assert first["mode"] == "window"
    assert first["scans"] == 601
    near = first["first_within"]
    assert near["time"]["offset_s"] == pytest.approx(lidar.FIRST_WITHIN_0_5_S, abs=0.1)  # within one scan period
    assert near["range_m"] == pytest.approx(lidar.RANGE_AT_FIRST_SCAN_M, abs=1e-3)
    assert near["bearing_deg"] == pytest.approx(lidar.BEARING_AT_FIRST_SCAN_DEG, abs=1.0)
    assert near["stays_s"] == pytest.approx(lidar.WITHIN_0_5_DURATION_S, abs=0.2)
    assert first["closest"]["range_m"] == pytest.approx(lidar.CLOSEST_RANGE_M, abs=1e-3)
    assert first["closest"]["time"]["offset_s"] == pytest.approx(lidar.CLOSEST_S, abs=0.1)
    one = await result(client, "analyze_lidar_scan", bag=bag, time=0)
    counts = lidar.beam_counts_at(0.0)
    scan = one["scan"]
    assert (scan["beams"], scan["valid"], scan["nan"], scan["pos_inf"], scan["below_min"]) == (
        lidar.BEAMS,
        counts.valid,
        counts.nan,
        counts.inf,
        counts.below_min,
    )
    cloud = (await result(client, "analyze_lidar_scan", bag=bag, topic=sensors.POINTS_TOPIC, time=5))["cloud"]
    assert cloud["points"] == sensors.POINT_COUNT
    assert cloud["closest"]["range_m"] == pytest.approx(sensors.CLOSEST_POINT_RANGE_M, abs=1e-5)


async def check_logs(client: Client, bag: str) -> None:
    found = await result(client, "analyze_logs", bag=bag, limit=5)
    assert found["total"] == logs.LOG_COUNT  # /rosout_agg copies (ROS 1) are counted once
    assert found["summary"]["by_level"] == logs.COUNTS_BY_LEVEL
    assert found["summary"]["by_node"] == logs.COUNTS_BY_NODE
    first_error = found["summary"]["first_error"]
    assert (first_error["text"], first_error["node"]) == (logs.FIRST_ERROR.text, logs.FIRST_ERROR.node)
    assert first_error["time"]["offset_s"] == pytest.approx(logs.FIRST_ERROR.t_s, abs=1e-6)
    burst = found["summary"]["bursts"][0]
    assert (burst["top_node"], burst["count"]) == (logs.BURST.node, logs.BURST.count)
    assert found["returned"] == 5
    assert found["next_offset"] == 5
    serious = await result(client, "analyze_logs", bag=bag, min_level="ERROR")
    assert serious["total"] == logs.COUNTS_BY_LEVEL["ERROR"] + logs.COUNTS_BY_LEVEL["FATAL"]
    exact = await result(client, "analyze_logs", bag=bag, level="warn", node="controller")
    assert exact["total"] == sum(1 for r in logs.LOGS if r.level == "WARN" and r.node == "/controller")
    assert "DEBUG, INFO, WARN" in await call_error(client, "analyze_logs", bag=bag, level="LOUD")


async def check_tf(client: Client, bag: str) -> None:
    tree = await result(client, "get_tf_tree", bag=bag)
    assert tree["roots"] == list(tf.ROOTS)
    assert set(tree["frames"]) == set(tf.FRAMES)
    assert {(e["parent"], e["child"], e["static"]) for e in tree["edges"]} == {
        (e.parent, e.child, e.static) for e in tf.EDGES
    }
    dynamic = next(e for e in tree["edges"] if not e["static"])
    assert dynamic["rate_hz"] == pytest.approx(20.0, rel=1e-3)
    for t in (0.0, 13.55, 24.7, 59.0):
        expected = tf.lookup_map_laser(t)
        got = await result(client, "lookup_transform", bag=bag, target_frame="map", source_frame="laser", time=t)
        assert got["translation_m"] == pytest.approx(list(expected.translation), abs=1e-6)
        assert got["rotation"] == pytest.approx(list(expected.rotation_xyzw), abs=1e-6)
        back = tf.lookup_laser_map(t)
        inverse = await result(client, "lookup_transform", bag=bag, target_frame="laser", source_frame="map", time=t)
        assert inverse["translation_m"] == pytest.approx(list(back.translation), abs=1e-6)
    assert "no_such_frame" in await call_error(
        client, "lookup_transform", bag=bag, target_frame="map", source_frame="no_such_frame"
    )


def _pixels(answer: Any) -> Image.Image:
    picture = next(c for c in answer.content if c.type == "image")
    return Image.open(io.BytesIO(base64.b64decode(picture.data))).convert("RGB")


async def check_images(client: Client, bag: str) -> None:
    for encoding, (topic, at_s) in images.IMAGE_TOPICS.items():
        answer = await client.call_tool("get_image_at_time", {"bag": bag, "topic": topic, "time": at_s})
        assert not answer.is_error, (encoding, answer.content)
        meta = answer.structured_content
        assert meta is not None
        assert (meta["encoding"], meta["width"], meta["height"]) == (encoding, 8, 6)
        shown = _pixels(answer)
        if encoding in images.GRADIENT_RANGES and meta["kind"] == "depth":
            low, high = images.GRADIENT_RANGES[encoding]
            assert (meta["depth"]["min_value"], meta["depth"]["max_value"]) == pytest.approx((low, high), rel=1e-6)
            continue
        for row, col in ((0, 0), (5, 7), (2, 3)):
            if meta["kind"] == "mono":
                grey = round(images.expected_value_at(encoding, row, col))
                expected: tuple[int, int, int] = (grey, grey, grey)
            else:
                expected = images.expected_rgb_at(encoding, row, col)
            assert shown.getpixel((col, row)) == pytest.approx(expected, abs=2), (encoding, row, col)
    for fmt, (topic, at_s) in images.COMPRESSED_TOPICS.items():
        answer = await client.call_tool("get_image_at_time", {"bag": bag, "topic": topic, "time": at_s})
        assert not answer.is_error, answer.content
        shown = _pixels(answer)
        assert shown.size == (64, 48)
        assert shown.getpixel((5, 20)) == pytest.approx((255, 0, 0), abs=8), fmt
        assert shown.getpixel((60, 20)) == pytest.approx((0, 0, 255), abs=8), fmt


async def check_statistics_and_window(client: Client, bag: str) -> None:
    imu = await result(client, "topic_statistics", bag=bag, topic=sensors.IMU_TOPIC)
    assert imu["count"] == sensors.IMU_COUNT
    assert imu["dropped_estimate"] == sensors.IMU_DROPPED
    gap = imu["gaps"][0]
    assert (gap["start"]["offset_s"], gap["end"]["offset_s"]) == pytest.approx(sensors.IMU_GAP_S, abs=1e-6)
    assert imu["header"]["delay_median_s"] == pytest.approx(sensors.IMU_STAMP_DELAY_S, abs=1e-6)
    periods = sensors.IMU_GAP_DURATION_S * sensors.IMU_HZ  # the gap lasts 100 median periods
    longer = await result(client, "topic_statistics", bag=bag, topic=sensors.IMU_TOPIC, gap_periods=periods + 1)
    assert (longer["gap_count"], longer["dropped_estimate"]) == (0, 0)
    shorter = await result(client, "topic_statistics", bag=bag, topic=sensors.IMU_TOPIC, gap_periods=periods - 1)
    assert (shorter["gap_count"], shorter["dropped_estimate"]) == (1, sensors.IMU_DROPPED)
    window = await result(client, "summarize_window", bag=bag, start=19, end=23)
    status = {t["topic"]: t["status"] for t in window["topics"]}
    assert status[sensors.IMU_TOPIC] == "gap"
    assert status["/odom"] == "ok"
    assert window["warnings"]["ERROR"] == 1
    assert any(sensors.IMU_TOPIC in s and "silent" in s for s in window["statements"])
    assert any(logs.FIRST_ERROR.text in s for s in window["statements"])
    assert window["motion"]["distance_m"] > 0


async def check_analysis(client: Client, bags: list[str]) -> None:
    for bag in bags:
        await check_trajectory(client, bag)
        await check_lidar(client, bag)
        await check_logs(client, bag)
        await check_tf(client, bag)
        await check_images(client, bag)
        await check_statistics_and_window(client, bag)
