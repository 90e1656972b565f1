"""Every analysis tool on the drive bags in three formats, through the in-process gateway."""

from __future__ import annotations

import pytest
from mcp import Client

from tests.checks import analysis_checks as checks
from tests.fixtures.inprocess import InProcess
from tests.unit.conftest import DRIVE_NAMES

pytestmark = pytest.mark.anyio


@pytest.mark.parametrize("bag", DRIVE_NAMES)
async def test_trajectory_matches_the_drive(served_drive: InProcess, bag: str) -> None:
    async with Client(served_drive.gateway(), cache=None) as client:
        await checks.check_trajectory(client, bag)


@pytest.mark.parametrize("bag", DRIVE_NAMES)
async def test_lidar_sees_the_post_when_the_geometry_says(served_drive: InProcess, bag: str) -> None:
    async with Client(served_drive.gateway(), cache=None) as client:
        await checks.check_lidar(client, bag)


@pytest.mark.parametrize("bag", DRIVE_NAMES)
async def test_logs_are_counted_exactly_in_both_ros_versions(served_drive: InProcess, bag: str) -> None:
    async with Client(served_drive.gateway(), cache=None) as client:
        await checks.check_logs(client, bag)


@pytest.mark.parametrize("bag", DRIVE_NAMES)
async def test_the_tf_tree_and_lookups_match_the_chains(served_drive: InProcess, bag: str) -> None:
    async with Client(served_drive.gateway(), cache=None) as client:
        await checks.check_tf(client, bag)


@pytest.mark.parametrize("bag", DRIVE_NAMES)
async def test_images_of_every_encoding_show_their_pixels(served_drive: InProcess, bag: str) -> None:
    async with Client(served_drive.gateway(), cache=None) as client:
        await checks.check_images(client, bag)


@pytest.mark.parametrize("bag", DRIVE_NAMES)
async def test_topic_statistics_and_window_summaries_find_the_imu_gap(served_drive: InProcess, bag: str) -> None:
    async with Client(served_drive.gateway(), cache=None) as client:
        await checks.check_statistics_and_window(client, bag)
