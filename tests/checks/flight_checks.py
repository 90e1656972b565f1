"""The tools on recordings that are not ROS bags (tests/fixtures/flight_files: a PX4 ULog, an ArduPilot
DataFlash log, JSON and protobuf MCAP), against the values the fixtures wrote (tests/fixtures/flight_plan).

Every way of serving runs these: the in-process gateway, `bagmcp serve` and the stack."""

from __future__ import annotations

from typing import Any

import pytest
from mcp import Client

from tests.checks.analysis_checks import result
from tests.checks.plot_checks import plot
from tests.fixtures import flight_plan as fp
from tests.fixtures.flight_files import DATAFLASH, JSON_MCAP, PROTOBUF_MCAP, ULOG
from tests.fixtures.mcp_client import call, call_error

Answer = dict[str, Any]
START_ISO = "2024-05-01T12:00:00Z"


async def check_listing(client: Client) -> None:
    bags = {b["name"]: b for b in (await call(client, "list_bags", limit=500))["bags"]}
    formats = {name: bags[name]["format"] for name in (ULOG, DATAFLASH, JSON_MCAP, PROTOBUF_MCAP)}
    assert formats == {ULOG: "px4-ulog", DATAFLASH: "ardupilot-dataflash", JSON_MCAP: "mcap", PROTOBUF_MCAP: "mcap"}
    assert all(bags[name]["status"] == "ready" for name in formats), bags
    info = await call(client, "bag_info", bag=ULOG)
    assert (info["duration_s"], info["start"]["iso"]) == (pytest.approx(fp.DURATION_S), START_ISO)
    assert {"logged_messages", "parameters", "sensor_accel/1"} <= {t["name"] for t in info["topics"]}
    assert any("50 ms" in n for n in info["notes"])


async def check_trajectories(client: Client) -> None:
    local = await result(client, "analyze_trajectory", bag=ULOG)
    assert (local["topic"], local["type"]) == ("vehicle_local_position", "px4/vehicle_local_position")
    assert local["distance_2d_m"] == pytest.approx(fp.PATH_M, rel=1e-3)
    assert local["max_speed_mps"] == pytest.approx(fp.SPEED_MPS, rel=0.02)
    assert "z down" in local["frame"]
    gps = await result(client, "analyze_trajectory", bag=ULOG, topic="vehicle_gps_position")
    assert gps["distance_2d_m"] == pytest.approx(fp.PATH_M, rel=0.01)
    pos = await result(client, "analyze_trajectory", bag=DATAFLASH)
    assert (pos["topic"], pos["distance_2d_m"]) == ("POS", pytest.approx(fp.PATH_M, rel=0.01))
    fixed = await result(client, "analyze_trajectory", bag=DATAFLASH, topic="GPS")  # no 3D fix in the first second
    assert fixed["distance_2d_m"] == pytest.approx(fp.PATH_M - fp.SPEED_MPS * 1.0, rel=0.01)


async def check_logs_and_modes(client: Client) -> None:
    px4 = await result(client, "analyze_logs", bag=ULOG)
    assert {k: v for k, v in px4["summary"]["by_level"].items() if v} == {"DEBUG": 1, "INFO": 1, "WARN": 1, "ERROR": 1}
    first_error = px4["summary"]["first_error"]
    assert (first_error["text"], first_error["node"], first_error["time"]["offset_s"]) == (
        "[ekf2] estimator failure",
        "ekf2",
        pytest.approx(16.0),
    )
    ardupilot = await result(client, "analyze_logs", bag=DATAFLASH, min_level="ERROR")
    assert [(e["text"], e["time"]["offset_s"]) for e in ardupilot["entries"]] == [
        ("EKF check error 2 (Subsys 16)", pytest.approx(12.0))
    ]
    for bag, column in ((ULOG, 2), (DATAFLASH, 4)):
        window = await result(client, "summarize_window", bag=bag, start=10, end=20)
        modes = [(m["mode"], m["since"]["offset_s"]) for m in window["flight_modes"]]
        assert modes == [(fp.MODES[1][column], pytest.approx(8.0)), (fp.MODES[2][column], pytest.approx(15.0))]
        assert window["statements"][0].startswith(f"flight modes: {fp.MODES[1][column]} from 8.0 s")


async def check_messages(client: Client) -> None:
    status = await call(client, "get_message_at_time", bag=ULOG, topic="vehicle_status", time=9)
    assert status["message"]["data"]["nav_state"] == fp.MODES[1][1]
    north = await result(
        client,
        "search_messages",
        bag=ULOG,
        topic="vehicle_local_position",
        field="y",
        condition="greater_than",
        value=5,
    )
    assert north["total"] == 50  # y = t - 10 after 10 s: above 5 m from 15.1 s to 20.0 s, 10 a second
    no_fix = await result(
        client, "search_messages", bag=DATAFLASH, topic="GPS", field="Status", condition="less_than", value=3
    )
    assert no_fix["total"] == 5
    changes = await result(
        client, "search_messages", bag=ULOG, topic="parameters", field="name", condition="contains", value="MPC"
    )
    assert changes["total"] == 2  # the initial value and the change
    pos = await call(client, "describe_topic", bag=DATAFLASH, topic="POS")
    units = {f["path"]: f["unit"] for f in pos["fields"]}
    assert (units["Alt"], units["TimeUS"], units["Lat"]) == ("m", "µs", "deglatitude")
    json_pose = await call(client, "get_messages_in_range", bag=JSON_MCAP, topic="/pose", max_messages=3)
    assert [m["data"]["x"] for m in json_pose["messages"]] == [0.0, 0.1, 0.2]
    far = await result(
        client, "search_messages", bag=PROTOBUF_MCAP, topic="/pose", field="x", condition="greater_than", value=4
    )
    assert far["total"] == 9
    rate = await result(client, "topic_statistics", bag=ULOG, topic="vehicle_local_position")
    assert rate["rate_hz"] == pytest.approx(10.0, rel=1e-3)


async def check_plots_and_refusals(client: Client) -> None:
    report, _ = await plot(
        client, "plot_timeseries", bag=ULOG, paths=["/vehicle_local_position.vx", "/vehicle_gps_position.vel_m_s"]
    )
    assert [(s["points"], s["max"]) for s in report["series"]] == [(201, pytest.approx(1.0)), (101, pytest.approx(1.0))]
    battery, _ = await plot(client, "plot_timeseries", bag=DATAFLASH, paths=["/BAT.Volt"])
    assert battery["series"][0]["unit"] == "V"
    assert "no TF topic" in await call_error(client, "get_tf_tree", bag=ULOG)
    assert "no LaserScan or PointCloud2 topic" in await call_error(client, "analyze_lidar_scan", bag=DATAFLASH)
    image = await call_error(client, "get_image_at_time", bag=ULOG, topic="vehicle_status", time=1)
    assert "give a sensor_msgs/Image or CompressedImage topic" in image


async def check_filtered_copies(client: Client) -> None:
    copy = await result(client, "filter_bag", bag=ULOG, include_topics=["vehicle_local_position"], name="flight-lp")
    assert (copy["format"], copy["counts"]) == ("mcap-json", {"vehicle_local_position": 201})
    again = await result(client, "analyze_trajectory", bag="flight-lp")
    assert again["distance_2d_m"] == pytest.approx(fp.PATH_M, rel=1e-3)
    refused = await call_error(client, "filter_bag", bag=DATAFLASH, include_topics=["GPS"], format="ros1")
    assert "write it as mcap-json" in refused


async def check_flight_logs(client: Client) -> None:
    await check_listing(client)
    await check_trajectories(client)
    await check_logs_and_modes(client)
    await check_messages(client)
    await check_plots_and_refusals(client)
    await check_filtered_copies(client)
