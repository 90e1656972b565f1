"""The real flight logs and the non-ROS MCAP of ../shared/data/bags through the bag layer, against the
libraries' own readings: every ULog topic with pyulog's count, every DataFlash type with the count and
the message times pymavlink gives when it walks the log, the data_tamer sample's values."""

from __future__ import annotations

from collections import Counter, defaultdict
from pathlib import Path

import pytest

from bagmcp_shared.bags import open_bag
from bagmcp_shared.timebase import iso_from_ns
from tests.conftest import CORPUS
from tests.fixtures.corpus_expectations import pymavlink_times, pyulog_counts

pytestmark = pytest.mark.corpus
ULOGS = sorted(p.name for p in (CORPUS / "px4_ulog").glob("*.ulg"))
DATAFLASH = ("uob_copter_4.3.6_loiter_rtl_2023-07-06.bin", "dronekit_la_copter_3.3_log171.bin")


@pytest.mark.parametrize("name", ULOGS)
def test_ulog_topics_and_counts_are_pyulogs(corpus: Path, name: str) -> None:
    path = corpus / "px4_ulog" / name
    expected, duration_s = pyulog_counts(path)
    with open_bag(path) as bag:
        summary = bag.summary()
        assert bag.decoder.problems == {}
    assert {t.name: t.count for t in summary.topics} == expected
    assert summary.duration_s == pytest.approx(duration_s, abs=1e-6)


def test_ulog_times_are_on_gps_utc_where_the_log_has_it(corpus: Path) -> None:
    with open_bag(corpus / "px4_ulog/flight_review_ekf_failure_manual_flight.ulg") as bag:
        summary = bag.summary()
    with open_bag(corpus / "px4_ulog/sample_appended_multiple.ulg") as bag:
        no_gps = bag.summary()
    assert iso_from_ns(summary.start_ns or 0).startswith("2025-02-10T13:56:29")  # SOURCES.md: GPS time 13:56:29
    assert iso_from_ns(summary.end_ns or 0).startswith("2025-02-10T13:57:48")
    assert no_gps.start_ns == 12100461 * 1000  # SOURCES.md: 12100461 us since boot
    assert any("appended data" in n for n in no_gps.notes)


@pytest.mark.parametrize("name", DATAFLASH)
def test_dataflash_counts_and_every_message_time_are_pymavlinks(corpus: Path, name: str) -> None:
    path = corpus / "ardupilot" / name
    expected = pymavlink_times(path)
    with open_bag(path) as bag:
        summary = bag.summary()
        ours: dict[str, list[float]] = defaultdict(list)
        for raw in bag.messages():
            ours[raw.connection.topic].append(raw.log_time_ns / 1e9)
        assert bag.decoder.problems == {}
    assert {t.name: t.count for t in summary.topics} == {k: len(v) for k, v in expected.items()}
    for topic, times in expected.items():
        assert sorted(ours[topic]) == pytest.approx(sorted(times), abs=2e-6), topic


def test_dataflash_mode_and_msg_records_decode_with_names(corpus: Path) -> None:
    with open_bag(corpus / "ardupilot/dronekit_la_copter_3.3_log171.bin") as bag:
        texts = [bag.decode(raw).Message for raw in bag.messages(["MSG"])]  # type: ignore[attr-defined]
        modes = Counter(bag.decode(raw).ModeNum for raw in bag.messages(["MODE"]))  # type: ignore[attr-defined]
    assert texts[0] == "APM:Copter V3.3-dev (ae3192b8)"
    assert modes == {5: 2, 1: 1}  # SOURCES.md: LOITER at start and at 63.2 s, ACRO at 205.8 s


def test_the_data_tamer_mcap_decodes_its_sample_values(corpus: Path) -> None:
    with open_bag(corpus / "edge_cases/mcap_non_ros_profile_data_tamer.mcap") as bag:
        a = bag.decode(next(bag.messages(["channelA"])))
        b = bag.decode(next(bag.messages(["channelB"])))
        assert bag.summary().profile == "data_tamer"
    assert a.array_4.tolist() == [1.0, 2.0, 3.0, 4.0]  # type: ignore[attr-defined]
    assert (a.val_int32, a.val_int16) == (5, 6)  # type: ignore[attr-defined]
    assert (a.pose.position.z, a.pose.rotation.w) == pytest.approx((3.0, 0.4))  # type: ignore[attr-defined]
    assert b.real_value == 10.0  # type: ignore[attr-defined]
    assert b.array_3.tolist() == [13, 14, 15]  # type: ignore[attr-defined]
    assert [(p.x, p.y, p.z) for p in b.points] == [(1.0, 2.0, 3.0), (4.0, 5.0, 6.0)]  # type: ignore[attr-defined]
