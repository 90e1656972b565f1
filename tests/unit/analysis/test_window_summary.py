"""summarize_window on a bag whose /imu arrives late for a while among many quiet topics: the late topic is
named with its delays, the topic list is bounded with totals, and stops come with their times."""

from __future__ import annotations

import pytest
from mcp import Client

from tests.checks.analysis_checks import result
from tests.fixtures import drive_scenario as drive
from tests.fixtures import small_bags as small
from tests.fixtures.inprocess import InProcess

pytestmark = pytest.mark.anyio


async def test_a_topic_whose_header_stamps_fall_behind_is_late_in_that_window(served_small: InProcess) -> None:
    async with Client(served_small.gateway(), cache=None) as client:
        window = await result(client, "summarize_window", bag="late_imu", start=10, end=12)
        imu = window["topics"][0]
        assert (imu["topic"], imu["status"]) == (small.IMU_TOPIC, "late")
        assert imu["delay_s"] == pytest.approx(small.LATE_DELAY_S, abs=1e-6)  # 100 of the 101 messages are late
        assert imu["bag_delay_s"] == pytest.approx(small.USUAL_DELAY_S, abs=1e-6)
        assert any(s.startswith(f"{small.IMU_TOPIC} arrived late") and "0.400 s" in s for s in window["statements"])
        calm = await result(client, "summarize_window", bag="late_imu", start=20, end=25)
        assert {t["status"] for t in calm["topics"]} == {"ok"}


async def test_the_topic_list_is_bounded_and_counts_every_topic(served_small: InProcess) -> None:
    async with Client(served_small.gateway(), cache=None) as client:
        window = await result(client, "summarize_window", bag="late_imu", start=10, end=12)
        assert window["topics_total"] == small.EXTRA_TOPICS + 1
        assert len(window["topics"]) == 25
        assert window["topics_by_status"] == {"late": 1, "ok": small.EXTRA_TOPICS}


async def test_stops_in_a_window_come_with_their_times(served_drive: InProcess) -> None:
    async with Client(served_drive.gateway(), cache=None) as client:
        window = await result(client, "summarize_window", bag="drive_mcap", start=0, end=21)
        motion = window["motion"]
        inside = [s for s in drive.STOPS_S if s[1] <= 21]
        assert motion["stop_count"] == len(inside)
        shown = [t for s in motion["stops"] for t in (s["start"]["offset_s"], s["end"]["offset_s"])]
        assert shown == pytest.approx([t for s in inside for t in s], abs=0.06)
        assert any("stops: 0.0-1.0 s, 5.0-8.0 s" in s for s in window["statements"])
