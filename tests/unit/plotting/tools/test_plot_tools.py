"""Every plotting tool on the drive bags in three formats, through the in-process gateway; GPS in metres,
compare_runs titles, stored plots as MCP resources."""

from __future__ import annotations

import base64
import io

import pytest
from mcp import Client, MCPError
from mcp.types import BlobResourceContents
from PIL import Image

from bagmcp_plotting.artifacts import ARTIFACT_URI
from tests.checks.analysis_checks import result
from tests.checks.plot_checks import check_plots, plot
from tests.fixtures import drive_sensors as sensors
from tests.fixtures.inprocess import InProcess
from tests.unit.conftest import DRIVE_NAMES

pytestmark = pytest.mark.anyio


@pytest.mark.parametrize("bag", DRIVE_NAMES)
async def test_every_plot_is_a_real_image_with_a_summary_that_matches_the_drive(
    served_drive: InProcess, bag: str
) -> None:
    other = next(b for b in DRIVE_NAMES if b != bag)
    async with Client(served_drive.gateway(), cache=None) as client:
        await check_plots(client, bag, other)


async def test_a_gps_trajectory_is_drawn_in_metres_east_and_north_of_the_first_fix(served_drive: InProcess) -> None:
    async with Client(served_drive.gateway(), cache=None) as client:
        report, _ = await plot(client, "plot_2d", bag="drive_mcap", topic=sensors.GPS_TOPIC)
        trajectory = await result(client, "analyze_trajectory", bag="drive_mcap", topic=sensors.GPS_TOPIC)
    east, north = report["series"]
    assert (east["name"], east["unit"], north["name"], north["unit"]) == (
        f"{sensors.GPS_TOPIC} east",
        "m",
        f"{sensors.GPS_TOPIC} north",
        "m",
    )
    assert (east["min"], east["max"]) == pytest.approx((0.0, 0.0), abs=1e-6)
    assert (north["min"], north["max"]) == pytest.approx((0.0, sensors.GPS_DISTANCE_M), abs=1e-6)
    assert north["points"] == sensors.GPS_COUNT
    assert trajectory["extents"]["max_y"] == pytest.approx(north["max"], abs=1e-9)  # one conversion for both


async def test_compare_runs_names_its_time_window(served_drive: InProcess) -> None:
    async with Client(served_drive.gateway(), cache=None) as client:
        report, _ = await plot(client, "compare_runs", bags=["drive", "drive_db3"], path="/cmd_vel.linear.x")
    assert report["title"] == "/cmd_vel.linear.x: drive, drive_db3 (0.0 to 60.0 s from each bag start)"


async def test_a_stored_plot_can_be_read_as_an_mcp_resource(served_drive: InProcess) -> None:
    async with Client(served_drive.service("plotting"), cache=None) as client:
        templates = (await client.list_resource_templates()).resource_templates
        assert [t.uri_template for t in templates] == [ARTIFACT_URI]
        report, picture = await plot(client, "plot_histogram", bag="drive", path="/imu.angular_velocity.z")
        uri = ARTIFACT_URI.format(artifact=report["artifact"]["id"])
        contents = (await client.read_resource(uri)).contents
        assert len(contents) == 1
        blob = contents[0]
        assert isinstance(blob, BlobResourceContents)
        assert blob.mime_type == "image/png"
        stored = Image.open(io.BytesIO(base64.b64decode(blob.blob)))
        assert stored.size == picture.size
        assert len(base64.b64decode(blob.blob)) == report["artifact"]["bytes"]
        with pytest.raises(MCPError, match="no plot artifact 'cafe'"):
            await client.read_resource(ARTIFACT_URI.format(artifact="cafe"))
