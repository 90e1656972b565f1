"""The tools on the real flight logs of ../shared/data/bags (skipped without it), against the figures in its
SOURCES.md: distances by local position and by GPS, the flight-mode changes, the log texts, and the
estimator glitch of the EKF-failure flight that an analysis must not hide."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest
from mcp import Client

from tests.checks.analysis_checks import result
from tests.fixtures.inprocess import InProcess, copy_bags, in_process

pytestmark = [pytest.mark.anyio, pytest.mark.corpus]
EKF, MOTOR = "flight_review_ekf_failure_manual_flight", "flight_review_motor_failure_mission_rtl"
UOB, DRONEKIT = "uob_copter_4.3.6_loiter_rtl_2023-07-06", "dronekit_la_copter_3.3_log171"
FILES = [f"px4_ulog/{EKF}.ulg", f"px4_ulog/{MOTOR}.ulg", f"ardupilot/{UOB}.bin", f"ardupilot/{DRONEKIT}.bin"]


@pytest.fixture(scope="module")
def flights(corpus: Path, tmp_path_factory: pytest.TempPathFactory) -> Iterator[InProcess]:
    folder = copy_bags([corpus / f for f in FILES], tmp_path_factory.mktemp("recorded-flights") / "bags")
    with in_process(folder, tmp_path_factory.mktemp("data"), timeout_s=300) as services:
        yield services


async def _modes(client: Client, bag: str) -> tuple[list[str], list[float]]:
    window = await result(client, "summarize_window", bag=bag)
    modes = window["flight_modes"]
    return [m["mode"] for m in modes], [m["since"]["offset_s"] for m in modes]


@pytest.mark.parametrize(
    ("bag", "topic", "metres"),
    [
        (EKF, None, 471.5),
        (EKF, "vehicle_gps_position", 447.7),
        (MOTOR, None, 78.4),
        (MOTOR, "vehicle_gps_position", 77.9),  # PX4 1.9: latitude in 1e-7 degrees, altitude in millimetres
        (UOB, None, 123.4),  # POS
        (UOB, "GPS", 121.7),
        (DRONEKIT, None, 405.1),  # a 2015 log without POS: GPS
    ],
)
async def test_flight_paths_are_as_long_as_the_corpus_says(
    flights: InProcess, bag: str, topic: str | None, metres: float
) -> None:
    async with Client(flights.gateway(), cache=None) as client:
        path = await result(client, "analyze_trajectory", bag=bag, **({"topic": topic} if topic else {}))
    assert path["distance_2d_m"] == pytest.approx(metres, rel=0.005)


async def test_flight_modes_change_when_the_corpus_says(flights: InProcess) -> None:
    async with Client(flights.gateway(), cache=None) as client:
        found = {bag: await _modes(client, bag) for bag in (EKF, MOTOR, UOB, DRONEKIT)}
    expected = {  # SOURCES.md; the mission flight's first vehicle_status comes 5.1 s into the log
        EKF: (["MANUAL", "POSCTL"], [0.0, 61.5]),
        MOTOR: (["AUTO_MISSION", "AUTO_RTL"], [5.1, 22.1]),
        UOB: (["LOITER", "RTL"], [0.1, 32.4]),
        DRONEKIT: (["LOITER", "LOITER", "ACRO"], [0.0, 63.2, 205.8]),
    }
    for bag, (names, times) in expected.items():
        assert found[bag][0] == names, bag
        assert found[bag][1] == pytest.approx(times, abs=0.1), bag


async def test_log_texts_and_errors_are_read_with_levels(flights: InProcess) -> None:
    async with Client(flights.gateway(), cache=None) as client:
        px4 = await result(client, "analyze_logs", bag=EKF, limit=20)
        ekf_check = await result(client, "analyze_logs", bag=DRONEKIT, min_level="ERROR")
        uob = await result(client, "analyze_logs", bag=UOB)
    texts = [e["text"] for e in px4["entries"]]
    assert px4["total"] == 13
    assert any("Takeoff detected" in t for t in texts)
    assert any("Failsafe activated" in t for t in texts)
    assert [(e["text"], round(e["time"]["offset_s"], 1)) for e in ekf_check["entries"]] == [
        ("EKF check error 2 (Subsys 16)", 230.4)
    ]
    assert uob["total"] == 15


async def test_the_estimator_glitch_of_the_ekf_failure_flight_is_found(flights: InProcess) -> None:
    async with Client(flights.gateway(), cache=None) as client:
        below = await result(
            client,
            "search_messages",
            bag=EKF,
            topic="vehicle_local_position",
            field="z",
            condition="greater_than",
            value=20,
        )
    assert below["total"] > 0
    assert max(m["value"] for m in below["matches"]) == pytest.approx(25.9, abs=0.1)
    assert 70.0 < below["matches"][0]["time"]["offset_s"] < 72.0
