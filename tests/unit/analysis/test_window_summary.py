"""summarize_window on a bag whose /imu arrives late for a while among many quiet topics: the late topic is
named with its delays, the topic list is bounded with totals, and stops come with their times."""

from __future__ import annotations

from typing import Any

import pytest
from mcp import Client

from bagmcp_analysis.queries import activity, statistics
from bagmcp_shared.access import OpenBag
from tests.checks.analysis_checks import result
from tests.fixtures import drive_scenario as drive
from tests.fixtures import small_bags as small
from tests.fixtures.inprocess import InProcess

pytestmark = pytest.mark.anyio


def stamps_read(monkeypatch: pytest.MonkeyPatch, topic: str) -> list[int]:
    """How many messages of ``topic`` each stamps_of call of the window summary returns."""
    counts: list[int] = []
    real = statistics.stamps_of

    def counted(ob: OpenBag, name: str, *args: Any, **options: Any) -> Any:
        found = real(ob, name, *args, **options)
        if name == topic:
            counts.append(len(found[0]))
        return found

    monkeypatch.setattr(activity, "stamps_of", counted)
    return counts


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


async def test_a_topic_the_index_does_not_hold_is_read_in_the_window_and_sampled_across_the_bag(
    served_small: InProcess, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Its baseline delay comes from a few stretches, not the whole topic (a 2 GB bag's image topic was
    decoded whole: 21-34 s cold for a 10 s window)."""
    read = stamps_read(monkeypatch, small.CAMERA_TOPIC)
    async with Client(served_small.gateway(), cache=None) as client:
        window = await result(client, "summarize_window", bag="late_camera", start=10, end=12)
    camera = window["topics"][0]
    assert (camera["topic"], camera["status"]) == (small.CAMERA_TOPIC, "late")
    assert camera["delay_s"] == pytest.approx(small.LATE_DELAY_S, abs=1e-6)
    assert camera["bag_delay_s"] == pytest.approx(small.USUAL_DELAY_S, abs=1e-6)
    whole = int(small.LATE_BAG_S * small.IMU_HZ) + 1
    assert camera["count"] + activity.SAMPLE_STRETCHES * activity.SAMPLE_MESSAGES <= sum(read) < whole // 4


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
