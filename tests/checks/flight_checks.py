"""The tools on recordings that are not ROS bags (tests/fixtures/flight_files: a PX4 ULog, an ArduPilot
DataFlash log, JSON and protobuf MCAP), against the values the fixtures wrote (tests/fixtures/flight_plan).

Every way of serving runs these: the in-process gateway, `bagmcp serve` and the stack."""

from __future__ import annotations

from typing import Any

import anyio
import pytest
from mcp import Client

from tests.checks.analysis_checks import result
from tests.checks.plot_checks import plot
from tests.fixtures import flight_plan as fp
from tests.fixtures.flight_files import DATAFLASH, JSON_MCAP, PROTOBUF_MCAP, ULOG
from tests.fixtures.mcp_client import call, call_error, ingested_bags, text_of

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


async def check_setpoint_against_actual(client: Client, bag: str) -> None:
    """plot_timeseries of the commanded against the flown velocity (flight_plan.setpoint_velocity; the setpoint's
    position is NaN, as PX4 leaves it under velocity control)."""
    setpoint, _ = await plot(
        client, "plot_timeseries", bag=bag, paths=["/vehicle_local_position_setpoint.vx", "/vehicle_local_position.vx"]
    )
    assert [(s["name"], s["points"], s["min"], s["max"]) for s in setpoint["series"]] == [
        ("vehicle_local_position_setpoint.vx", 101, 0.0, pytest.approx(fp.SETPOINT_SPEED_MPS)),
        ("vehicle_local_position.vx", 201, 0.0, pytest.approx(fp.SPEED_MPS)),
    ]
    east, _ = await plot(
        client,
        "plot_timeseries",
        bag=bag,
        paths=["/vehicle_local_position_setpoint.vy", "/vehicle_local_position.vy"],
        start=11,
        end=20,
    )  # the east leg: the setpoint asks 1.2 m/s throughout, the vehicle flies at 1 m/s
    assert [(s["points"], s["min"], s["max"]) for s in east["series"]] == [
        (46, pytest.approx(fp.SETPOINT_SPEED_MPS), pytest.approx(fp.SETPOINT_SPEED_MPS)),
        (91, pytest.approx(fp.SPEED_MPS), pytest.approx(fp.SPEED_MPS)),
    ]


async def check_plots_and_refusals(client: Client) -> None:
    report, _ = await plot(
        client, "plot_timeseries", bag=ULOG, paths=["/vehicle_local_position.vx", "/vehicle_gps_position.vel_m_s"]
    )
    assert [(s["points"], s["max"]) for s in report["series"]] == [(201, pytest.approx(1.0)), (101, pytest.approx(1.0))]
    await check_setpoint_against_actual(client, ULOG)
    battery, _ = await plot(client, "plot_timeseries", bag=DATAFLASH, paths=["/BAT.Volt"])
    assert battery["series"][0]["unit"] == "V"
    assert "no TF topic" in await call_error(client, "get_tf_tree", bag=ULOG)
    assert "no LaserScan or PointCloud2 topic" in await call_error(client, "analyze_lidar_scan", bag=DATAFLASH)
    image = await call_error(client, "get_image_at_time", bag=ULOG, topic="vehicle_status", time=1)
    assert "give a sensor_msgs/Image or CompressedImage topic" in image


async def check_filtered_copies(client: Client) -> None:
    topics = ["vehicle_local_position", "vehicle_local_position_setpoint"]
    copy = await result(client, "filter_bag", bag=ULOG, include_topics=topics, name="flight-lp")
    assert (copy["format"], copy["counts"]) == ("mcap-json", {topics[0]: 201, topics[1]: 101})
    again = await result(client, "analyze_trajectory", bag="flight-lp")
    assert again["distance_2d_m"] == pytest.approx(fp.PATH_M, rel=1e-3)
    await check_setpoint_against_actual(client, "flight-lp")  # NaN went to JSON as null: the index reads it as NaN
    refused = await refusal(client, "filter_bag", bag=DATAFLASH, include_topics=["GPS"], format="ros1")
    assert "write it as mcap-json" in refused


async def refusal(client: Client, tool: str, **arguments: object) -> str:
    """The error of a call that must fail, whether at once or, past the time budget, as its job's error."""
    answer = await client.call_tool(tool, arguments)
    if answer.is_error:
        return text_of(answer)
    started = answer.structured_content
    assert started is not None
    assert "job" in started, text_of(answer)[:300]
    job = await ended(client, started["job"]["job_id"])
    assert job["state"] == "failed", job
    return str(job["error"])


async def ended(client: Client, job_id: str) -> Answer:
    """get_job's answer once the job has ended."""
    with anyio.fail_after(120):
        while (job := await call(client, "get_job", job_id=job_id))["state"] in ("queued", "running"):
            await anyio.sleep(0.1)
    return job


def one_line_refusal(text: str, tool: str, reason: str = "") -> None:
    """A refusal of ``tool`` in one line that gives the reason."""
    assert text.startswith(f"Error executing tool {tool}: "), text
    assert "\n" not in text.strip(), text
    assert reason in text, text


def _matches(found: Answer) -> dict[str, list[str]]:
    return {m["bag"]: [e["detail"] for e in m["evidence"]] for m in found["matches"]}


async def check_fleet_and_other_plots(client: Client) -> None:
    """find_bags, compare_runs, plot_2d, plot_histogram; plot_lidar_scan and lookup_transform refuse."""
    moving = _matches(await result(client, "find_bags", speed_above=0.5, topic="vehicle_local_position"))
    assert moving[ULOG] == [  # the ULog's own path (other bags where the stack is shared may match too)
        "vehicle_local_position (px4/vehicle_local_position): 201 messages",
        "max speed 1.000 m/s at 8.40 s on vehicle_local_position at (8.40, 0.00)",
    ]
    errors = _matches(await result(client, "find_bags", log_level="ERROR", topic="vehicle_status"))
    assert errors[ULOG][1] == "1 records; first at 16.00 s: [ERROR] ekf2: [ekf2] estimator failure"
    ardupilot = _matches(await result(client, "find_bags", log_level="ERROR", topic="POS"))
    assert ardupilot[DATAFLASH][1] == "1 records; first at 12.00 s: [ERROR] ardupilot: EKF check error 2 (Subsys 16)"
    runs, _ = await plot(client, "compare_runs", bags=[JSON_MCAP, PROTOBUF_MCAP], path="/pose.x")
    assert [(s["name"], s["points"], s["min"], s["max"]) for s in runs["series"]] == [
        (f"{JSON_MCAP}: /pose.x", 50, 0.0, pytest.approx(4.9)),
        (f"{PROTOBUF_MCAP}: /pose.x", 50, 0.0, pytest.approx(4.9)),
    ]
    other = await call_error(client, "compare_runs", bags=[ULOG, DATAFLASH], path="/vehicle_local_position.vx")
    one_line_refusal(other, "compare_runs", "topic '/vehicle_local_position' is not in")
    path, _ = await plot(client, "plot_2d", bag=ULOG)
    assert [(s["name"], s["points"], s["min"], s["max"]) for s in path["series"]] == [
        ("vehicle_local_position.x", 201, 0.0, pytest.approx(10.0)),
        ("vehicle_local_position.y", 201, 0.0, pytest.approx(10.0)),
    ]
    pos, _ = await plot(client, "plot_2d", bag=DATAFLASH)
    assert [(s["name"], s["points"], s["unit"]) for s in pos["series"]] == [
        ("POS east", 201, "m"),
        ("POS north", 201, "m"),
    ]
    assert [s["max"] for s in pos["series"]] == pytest.approx([10.0, 10.0], abs=0.01)
    flat = await call_error(client, "plot_2d", bag=JSON_MCAP)
    one_line_refusal(flat, "plot_2d", "has no odometry, pose, transform or GPS topic")
    speeds, _ = await plot(client, "plot_histogram", bag=ULOG, path="/vehicle_local_position.vx", bins=10)
    assert [(s["points"], s["min"], s["max"]) for s in speeds["series"]] == [(201, 0.0, pytest.approx(fp.SPEED_MPS))]
    xs, _ = await plot(client, "plot_histogram", bag=PROTOBUF_MCAP, path="/pose.x")
    assert [(s["points"], s["min"], s["max"]) for s in xs["series"]] == [(50, 0.0, pytest.approx(4.9))]
    one_line_refusal(
        await call_error(client, "plot_lidar_scan", bag=ULOG, time=1), "plot_lidar_scan", "no LaserScan or PointCloud2"
    )
    no_tf = await call_error(client, "lookup_transform", bag=DATAFLASH, target_frame="map", source_frame="base_link")
    one_line_refusal(no_tf, "lookup_transform", "has no TF topic")


async def check_cancelled_filter(
    client: Client, bag: str = ULOG, topic: str | None = "vehicle_gps_position", *, need_job: bool = True
) -> None:
    """cancel_job on a filter_bag job copying ``topic`` (None: every topic) of a flight log: the serving mode's
    time budget must be shorter than the filter, so that the answer is a job (``need_job`` False: a copy that
    finished within the budget, on a machine faster than this one, is checked whole instead). A small copy may
    be written before the worker looks at the request: the job then ends either cancelled, with no bag left,
    or succeeded with the whole copy (every message of the topics); never failed or half-done."""
    asked = f"{bag}-cancel"
    topics = {t["name"]: t["count"] for t in (await call(client, "bag_info", bag=bag))["topics"]}
    wanted = {topic: topics[topic]} if topic else {name: count for name, count in topics.items() if count}
    answer = await call(client, "filter_bag", bag=bag, name=asked, **({"include_topics": [topic]} if topic else {}))
    if "job" not in answer and not need_job:  # a machine fast enough to copy within the time budget
        assert (answer["name"], answer["counts"]) == (asked, wanted), answer
        return
    assert "job" in answer, answer
    job_id = answer["job"]["job_id"]
    cancel = await call(client, "cancel_job", job_id=job_id)
    assert (cancel["job_id"], cancel["kind"]) == (job_id, "bag_store.filter")
    assert cancel["message"] == "cancellation requested" or cancel["state"] in ("cancelled", "succeeded"), cancel
    job = await ended(client, job_id)
    listed = {b["name"] for b in await ingested_bags(client)}
    if job["state"] == "cancelled":
        assert (job["result"], job["error"], asked in listed) == (None, None, False), job
        assert job["message"] in ("cancelled", "cancelled before it started")
    else:
        assert job["state"] == "succeeded", job
        assert (job["result"]["name"], job["result"]["counts"]) == (asked, wanted)
        assert asked in listed
    again = await call(client, "cancel_job", job_id=job_id)  # an ended job stays as it ended
    assert (again["state"], again["result"]) == (job["state"], job["result"])


async def check_flight_logs(client: Client, *, cancel: bool = True) -> None:
    """Every check; ``cancel`` False where the time budget outlasts filtering these small logs (the stack's 1 s:
    its corpus test cancels a filter of a large real log instead)."""
    await check_listing(client)
    await check_trajectories(client)
    await check_logs_and_modes(client)
    await check_messages(client)
    await check_plots_and_refusals(client)
    await check_filtered_copies(client)
    await check_fleet_and_other_plots(client)
    if cancel:
        await check_cancelled_filter(client)
