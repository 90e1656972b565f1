"""Every tool on a PX4 ULog, an ArduPilot DataFlash log, JSON and protobuf MCAP, through the in-process
gateway over a served folder (which also holds a firmware .bin that is not listed)."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest
from mcp import Client

from tests.checks import flight_checks as checks
from tests.fixtures.flight_files import write_firmware, write_flight_files
from tests.fixtures.inprocess import InProcess, in_process
from tests.fixtures.mcp_client import call

pytestmark = pytest.mark.anyio


@pytest.fixture(scope="module")
def served_flights(tmp_path_factory: pytest.TempPathFactory) -> Iterator[InProcess]:
    folder = tmp_path_factory.mktemp("flights")
    write_flight_files(folder)
    write_firmware(folder)
    with in_process(folder, tmp_path_factory.mktemp("data")) as services:
        yield services


async def test_flight_logs_and_non_ros_mcap_are_listed_and_firmware_is_not(served_flights: InProcess) -> None:
    async with Client(served_flights.gateway(), cache=None) as client:
        await checks.check_listing(client)
        names = {b["name"] for b in (await call(client, "list_bags", limit=500))["bags"]}
    assert not any("fmu" in name for name in names)


async def test_trajectories_come_from_local_position_pos_and_gps(served_flights: InProcess) -> None:
    async with Client(served_flights.gateway(), cache=None) as client:
        await checks.check_trajectories(client)


async def test_log_texts_have_ros_levels_and_modes_form_a_timeline(served_flights: InProcess) -> None:
    async with Client(served_flights.gateway(), cache=None) as client:
        await checks.check_logs_and_modes(client)


async def test_messages_search_units_and_statistics(served_flights: InProcess) -> None:
    async with Client(served_flights.gateway(), cache=None) as client:
        await checks.check_messages(client)


async def test_plots_draw_and_tools_needing_tf_lidar_or_images_say_why_not(served_flights: InProcess) -> None:
    async with Client(served_flights.gateway(), cache=None) as client:
        await checks.check_plots_and_refusals(client)


async def test_filtered_copies_are_json_mcap_that_every_tool_reads(served_flights: InProcess) -> None:
    async with Client(served_flights.gateway(), cache=None) as client:
        await checks.check_filtered_copies(client)


async def test_fleet_search_comparisons_and_2d_plots_answer_lidar_and_tf_refuse(served_flights: InProcess) -> None:
    async with Client(served_flights.gateway(), cache=None) as client:
        await checks.check_fleet_and_other_plots(client)


async def test_cancel_job_on_a_filter_bag_job_leaves_no_half_done_copy(tmp_path: Path) -> None:
    write_flight_files(tmp_path / "flights")
    with in_process(tmp_path / "flights", tmp_path / "data", job_budget_s=0.0) as hurried:  # every long call: a job
        async with Client(hurried.gateway(), cache=None) as client:
            await checks.check_cancelled_filter(client)
