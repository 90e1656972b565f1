"""The analysis and plotting tools give sane answers on real recordings (skipped without the corpus):
the Husky drive (and the Jackal's, to compare runs), the nav2 TurtleBot MCAP, the tilt-laser scans, the rosout
logs, the compressed camera."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest
from mcp import Client

from tests.checks.plot_checks import plot
from tests.checks.search_checks import finished
from tests.fixtures.inprocess import InProcess, copy_bags, in_process
from tests.fixtures.mcp_client import call

pytestmark = [pytest.mark.anyio, pytest.mark.corpus]
FILES = [
    "ros1/husky_gps_imu_odom/test1.bag",
    "ros1/jackal_imu_odom/test2.bag",
    "ros2_mcap/evo_nav2_turtlebot/nav2_turtlebot.mcap",
    "ros1/tilt_laser_gps_imu/tilt_laser.bag",
    "ros1/rosout_log/out.bag",
    "ros1/fiducials_compressed_image/aruco_images.bag",
]


@pytest.fixture(scope="module")
def recorded(corpus: Path, tmp_path_factory: pytest.TempPathFactory) -> Iterator[InProcess]:
    folder = copy_bags([corpus / f for f in FILES], tmp_path_factory.mktemp("recorded") / "bags")
    with in_process(folder, tmp_path_factory.mktemp("data")) as services:
        yield services


async def _result(client: Client, tool: str, **arguments: object) -> dict[str, object]:
    return await finished(client, await call(client, tool, **arguments), timeout_s=120)


async def test_the_husky_drive_is_about_359_m_at_walking_speed(recorded: InProcess) -> None:
    async with Client(recorded.gateway(), cache=None) as client:
        path = await _result(client, "analyze_trajectory", bag="test1")
        assert path["topic"] == "/husky_velocity_controller/odom"
        assert path["distance_2d_m"] == pytest.approx(359, rel=0.02)
        assert 0.5 < path["max_speed_mps"] < 2.0  # type: ignore[operator]
        gps = await _result(client, "analyze_trajectory", bag="test1", topic="/fix")
        assert 300 < gps["distance_2d_m"] < 450  # type: ignore[operator]
        await plot(
            client, "plot_timeseries", bag="test1", paths=["/husky_velocity_controller/odom.twist.twist.linear.x"]
        )


async def test_the_nav2_turtlebot_has_a_map_rooted_tree_and_a_34_m_path(recorded: InProcess) -> None:
    async with Client(recorded.gateway(), cache=None) as client:
        path = await _result(client, "analyze_trajectory", bag="nav2_turtlebot")
        assert path["distance_2d_m"] == pytest.approx(34, rel=0.05)
        assert path["clock"] == "header"  # a simulation's clock, far from log time, but consistent
        assert path["max_speed_mps"] == pytest.approx(0.5, abs=0.005)  # the twist never exceeds 0.500
        window = await _result(client, "summarize_window", bag="nav2_turtlebot")
        assert window["motion"]["max_speed_mps"] == pytest.approx(0.5, abs=0.005)  # type: ignore[index]
        tree = await _result(client, "get_tf_tree", bag="nav2_turtlebot")
        assert tree["roots"] == ["map"]
        assert len(tree["frames"]) > 25  # type: ignore[arg-type]
        pose = await _result(
            client, "lookup_transform", bag="nav2_turtlebot", target_frame="map", source_frame="base_link", time=50
        )
        assert pose["chain"] == ["base_link", "odom", "map"]
        assert pose["extrapolated_s"] < 1.0  # type: ignore[operator]
        await plot(client, "plot_2d", bag="nav2_turtlebot")


async def test_the_tilt_laser_counts_invalid_beams_and_finds_the_closest_return(recorded: InProcess) -> None:
    async with Client(recorded.gateway(), cache=None) as client:
        one = await _result(client, "analyze_lidar_scan", bag="tilt_laser", time=5)
        scan = one["scan"]
        assert scan["beams"] == 1078  # type: ignore[index]
        assert 0 < scan["valid"] < scan["beams"]  # type: ignore[index]
        assert scan["closest"]["range_m"] > 0  # type: ignore[index]
        window = await _result(client, "analyze_lidar_scan", bag="tilt_laser", within=1.0)
        assert window["scans"] == 178
        assert window["first_within"] is not None
        await plot(client, "plot_lidar_scan", bag="tilt_laser", time=5, within=1.0)


async def test_the_rosout_bag_has_98_info_and_96_warn_records(recorded: InProcess) -> None:
    async with Client(recorded.gateway(), cache=None) as client:
        found = await _result(client, "analyze_logs", bag="out")
        assert found["topics"] == ["rosout"]
        assert found["summary"]["by_level"] == {"DEBUG": 0, "INFO": 98, "WARN": 96, "ERROR": 0, "FATAL": 0}  # type: ignore[index]
        await plot(client, "plot_histogram", bag="out", path="rosout.level")


async def test_the_compressed_camera_image_comes_back_as_a_smaller_jpeg(recorded: InProcess) -> None:
    async with Client(recorded.gateway(), cache=None) as client:
        answer = await client.call_tool(
            "get_image_at_time", {"bag": "aruco_images", "topic": "/raspicam_node/image/compressed", "time": 0}
        )
        meta = answer.structured_content
        assert meta is not None
        assert (meta["width"], meta["height"], meta["sent_width"], meta["mime_type"]) == (1280, 960, 1024, "image/jpeg")
        assert any(c.type == "image" for c in answer.content)


async def test_the_husky_and_jackal_runs_compare_and_the_husky_gps_plots_in_metres(recorded: InProcess) -> None:
    async with Client(recorded.gateway(), cache=None) as client:
        path = "/imu/data.angular_velocity.z"
        runs, _ = await plot(client, "compare_runs", bags=["test1", "test2"], path=path, align="motion")
        assert runs["bags"] == ["test1", "test2"]
        assert [s["points"] for s in runs["series"]] == [11865, 3061]
        assert runs["title"].startswith(f"{path}: test1, test2 (")
        assert runs["title"].endswith(" s from each first motion)")
        assert runs["notes"] == []  # both found their first motion on their odometry
        fixes, _ = await plot(client, "plot_2d", bag="test1", topic="/fix")
        east, north = fixes["series"]
        assert (east["unit"], north["unit"]) == ("m", "m")
        for axis in (east, north):
            assert 20 < axis["max"] - axis["min"] < 500  # a drive of a few hundred metres, not degrees
