"""Generated PX4 ULog and ArduPilot DataFlash logs (tests/fixtures, values in flight_plan) read through the
bag layer: topics and counts, UTC or since-boot times, decoded values with units and multipliers applied,
message paths, log records with ROS level names, parameters, flight modes and the index's columns."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from bagmcp_shared.bags import BagFormat, open_bag
from bagmcp_shared.errors import DamagedBagError
from bagmcp_shared.flight_modes import mode_changes, mode_topic, modes_in_window
from bagmcp_shared.index import build_index
from bagmcp_shared.index.column_index import ColumnIndex
from bagmcp_shared.index.logs import decode_logs
from bagmcp_shared.log_levels import level_name
from bagmcp_shared.paths import check_steps, extract, field_paths, parse_field_path
from tests.fixtures import flight_plan as fp
from tests.fixtures.dataflash_writer import COUNTS as DATAFLASH_COUNTS
from tests.fixtures.dataflash_writer import write_dataflash
from tests.fixtures.ulog_writer import COUNTS, COUNTS_ACCEL_1, write_ulog

START_NS = round(fp.UTC_START.timestamp() * 1e9)


@pytest.fixture(scope="module")
def ulog(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return write_ulog(tmp_path_factory.mktemp("ulog") / "flight.ulg")


@pytest.fixture(scope="module")
def dataflash(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return write_dataflash(tmp_path_factory.mktemp("dataflash") / "00000042.BIN")


def test_ulog_topics_are_message_names_and_instances_with_derived_records(ulog: Path) -> None:
    with open_bag(ulog) as bag:
        summary = bag.summary()
    counts = {t.name: t.count for t in summary.topics}
    assert summary.format is BagFormat.ULOG
    assert counts == {
        **COUNTS,
        "sensor_accel/1": COUNTS_ACCEL_1,
        "logged_messages": len(fp.PX4_TEXTS) + 1,
        "parameters": len(fp.PARAMETERS) + 1,
    }
    assert summary.topic("vehicle_local_position").msgtype == "px4/vehicle_local_position"  # type: ignore[union-attr]
    assert any("1 dropouts" in n and "50 ms" in n for n in summary.notes)


def test_ulog_times_are_utc_from_gps_and_samples_before_the_log_start_are_logged_at_it(ulog: Path) -> None:
    with open_bag(ulog) as bag:
        summary = bag.summary()
        status = list(bag.messages(["vehicle_status"]))
        early = bag.decode(status[0])
    assert summary.start_ns == START_NS
    assert summary.end_ns == START_NS + round(fp.DURATION_S * 1e9)
    assert status[0].log_time_ns == START_NS  # stamped 5 s before logging started
    assert early.timestamp == round((fp.BOOT_S - 5.0) * 1e6)  # type: ignore[attr-defined]
    assert any("UTC" in n for n in summary.notes)


def test_ulog_without_gps_time_stays_on_time_since_boot(tmp_path: Path) -> None:
    with open_bag(write_ulog(tmp_path / "no_gps.ulg", utc=False)) as bag:
        summary = bag.summary()
    assert summary.start_ns == round(fp.BOOT_S * 1e9)
    assert any("since the flight controller booted" in n for n in summary.notes)


def test_ulog_fields_decode_with_types_nested_formats_arrays_and_text(ulog: Path) -> None:
    with open_bag(ulog) as bag:
        at_15 = bag.decode(next(bag.messages(["vehicle_local_position"], start_ns=START_NS + 15 * 10**9)))
        accel = bag.decode(next(bag.messages(["sensor_accel/1"], start_ns=START_NS + 2 * 10**9)))
        store = bag.decoder.typestore("px4/sensor_accel")
    assert (at_15.x, at_15.y, at_15.z) == pytest.approx((10.0, 5.0, -5.0))  # type: ignore[attr-defined]
    assert at_15.heading == pytest.approx(math.pi / 2)  # type: ignore[attr-defined]
    assert at_15.xy_valid is True  # type: ignore[attr-defined]
    assert accel.samples[1].y == pytest.approx(-2.0)  # type: ignore[attr-defined]
    assert accel.name == "acc1"  # type: ignore[attr-defined]
    assert accel.raw.tolist() == [1, -2, 1]  # type: ignore[attr-defined]
    paths = dict(field_paths(store, "px4/sensor_accel"))
    assert paths["samples[0].z"] == "float32"
    assert paths["raw"] == "int16[3]"
    assert not any("_padding" in p for p in paths)
    steps = parse_field_path("samples[1].x")
    assert check_steps(store, "px4/sensor_accel", steps) == "float32"
    assert extract(accel, steps) == pytest.approx(1.0)


def test_ulog_logged_strings_become_log_rows_with_ros_level_names_and_modules_as_nodes(ulog: Path) -> None:
    with open_bag(ulog) as bag:
        rows = decode_logs(bag, "logged_messages")
    expected = [(t, text, name) for t, _, text, name in fp.PX4_TEXTS] + [
        (fp.PX4_TAGGED[0], fp.PX4_TAGGED[3], fp.PX4_TAGGED[4])
    ]
    assert [(round((r.t_ns - START_NS) / 1e9, 3), r.text, level_name(r.level, ros2=False)) for r in rows] == expected
    assert [r.node for r in rows] == ["commander", "navigator", "ekf2", "logger"]


def test_ulog_parameters_are_a_topic_with_initial_values_then_changes(ulog: Path) -> None:
    with open_bag(ulog) as bag:
        found = [(raw.log_time_ns, bag.decode(raw)) for raw in bag.messages(["parameters"])]
    values = [((t - START_NS) / 1e9, m.name, m.value, m.initial) for t, m in found]  # type: ignore[attr-defined]
    assert values == [
        (0.0, "MPC_XY_VEL_MAX", 12.0, True),
        (0.0, "SYS_AUTOSTART", 4001.0, True),
        (fp.PARAMETER_CHANGE[0], "MPC_XY_VEL_MAX", 8.0, False),
    ]


@pytest.mark.parametrize("which", ["ulog", "dataflash"])
def test_flight_modes_are_a_timeline_named_as_the_autopilot_names_them(which: str, ulog: Path, dataflash: Path) -> None:
    with open_bag(ulog if which == "ulog" else dataflash) as bag:
        topic = mode_topic(bag)
        assert topic is not None
        changes = mode_changes(bag, topic)
    column = 2 if which == "ulog" else 4
    assert [((c.t_ns - START_NS) / 1e9, c.name) for c in changes] == [(m[0], m[column]) for m in fp.MODES]
    window = modes_in_window(changes, START_NS + 10 * 10**9, START_NS + 20 * 10**9)
    assert [c.name for c in window] == [fp.MODES[1][column], fp.MODES[2][column]]  # the mode in effect, then RTL


def test_dataflash_types_are_topics_with_pymavlink_multipliers_and_units(dataflash: Path) -> None:
    with open_bag(dataflash) as bag:
        summary = bag.summary()
        gps = bag.decode(next(bag.messages(["GPS"], start_ns=START_NS + 15 * 10**9)))
        att = bag.decode(next(bag.messages(["ATT"])))
        units = bag.decoder.units("ardupilot/POS")
    counts = {t.name: t.count for t in summary.topics}
    assert {k: counts[k] for k in DATAFLASH_COUNTS} == DATAFLASH_COUNTS
    assert summary.format is BagFormat.DATAFLASH
    assert summary.start_ns == START_NS
    assert gps.Lat == pytest.approx(fp.at(15.0).latitude, abs=1e-7)  # type: ignore[attr-defined]  # L: 1e-7 deg
    assert gps.Alt == pytest.approx(fp.ORIGIN[2] + fp.ALTITUDE_M)  # type: ignore[attr-defined]  # e: centimetres
    assert gps.HDop == pytest.approx(0.7)  # type: ignore[attr-defined]  # c: hundredths
    assert (att.Roll, att.Pitch) == pytest.approx((1.5, -2.5))  # type: ignore[attr-defined]
    assert units == {"TimeUS": "µs", "Lat": "deglatitude", "Lng": "deglongitude", "Alt": "m", "RelHomeAlt": "m"}


def test_dataflash_msg_and_err_are_log_records(dataflash: Path) -> None:
    with open_bag(dataflash) as bag:
        texts = decode_logs(bag, "MSG")
        errors = decode_logs(bag, "ERR")
    assert [r.text for r in texts] == [t for _, t in fp.ARDUPILOT_TEXTS]
    assert {level_name(r.level, ros2=False) for r in texts} == {"INFO"}
    assert [(level_name(r.level, ros2=False), r.text) for r in errors] == [
        ("ERROR", "EKF check error 2 (Subsys 16)"),
        ("INFO", "EKF check error cleared (Subsys 16)"),
    ]


def test_the_index_extracts_flight_columns_and_records(ulog: Path, dataflash: Path, tmp_path: Path) -> None:
    with open_bag(ulog) as bag:
        manifest = build_index(bag, tmp_path / "ulog")
    assert set(manifest["topics"]) >= {"vehicle_local_position", "vehicle_gps_position", "vehicle_status"}  # type: ignore[call-overload]
    assert set(manifest["logs"]) == {"logged_messages"}  # type: ignore[call-overload]
    index = ColumnIndex.load(tmp_path / "ulog")
    assert index is not None
    series = index.read("vehicle_local_position", ["x", "y"])
    assert float(np.max(series.columns["x"])) == pytest.approx(10.0)
    assert float(series.columns["y"][-1]) == pytest.approx(10.0)
    with open_bag(dataflash) as bag:
        manifest = build_index(bag, tmp_path / "dataflash")
    assert set(manifest["logs"]) == {"MSG", "ERR"}  # type: ignore[call-overload]
    assert manifest["topics"]["POS"]["count"] == DATAFLASH_COUNTS["POS"]  # type: ignore[index]


@pytest.mark.parametrize(
    ("content", "phrase"),
    [(b"ULog\x01\x12\x35\x01" + bytes(64), "holds no message formats"), (b"\xa3\x95\x80", "no complete record")],
)
def test_a_flight_log_with_nothing_in_it_is_damaged(tmp_path: Path, content: bytes, phrase: str) -> None:
    path = tmp_path / ("empty.ulg" if content.startswith(b"ULog") else "empty.bin")
    path.write_bytes(content)
    with pytest.raises(DamagedBagError, match=phrase):
        open_bag(path)
