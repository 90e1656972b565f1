"""Filtered copies of flight logs and non-ROS MCAP are MCAP with JSON messages that bagmcp reads back with
the same topics, types, times and values; ROS formats are refused for them, and JSON MCAP for ROS bags."""

from __future__ import annotations

from pathlib import Path

import pytest

from bagmcp_shared.bags import Encoding, open_bag
from bagmcp_shared.bags.writer import FilterError, FilterSpec, OutputFormat, default_output, write_filtered
from bagmcp_shared.flight_modes import mode_changes
from tests.fixtures import flight_plan as fp
from tests.fixtures.bagfactory import write_bag
from tests.fixtures.dataflash_writer import write_dataflash
from tests.fixtures.foreign_mcap import write_protobuf_mcap
from tests.fixtures.ulog_writer import COUNTS, write_ulog


def _copy(source: Path, out: Path, spec: FilterSpec, fmt: OutputFormat | None = None) -> Path:
    with open_bag(source) as bag:
        chosen = fmt or default_output(bag.format, bag.connections)
        return write_filtered(bag, out, "copy", fmt=chosen, spec=spec).path


def _everything(path: Path, topic: str) -> list[tuple[int, object]]:
    with open_bag(path) as bag:
        return [(raw.log_time_ns, bag.decode(raw)) for raw in bag.messages([topic])]


def test_a_ulog_selection_is_json_mcap_with_the_same_times_and_values(tmp_path: Path) -> None:
    source = write_ulog(tmp_path / "flight.ulg")
    spec = FilterSpec(include_topics=("vehicle_local_position", "logged_messages", "sensor_accel/1"))
    copy = _copy(source, tmp_path, spec)
    assert copy.suffix == ".mcap"
    with open_bag(copy) as bag:
        assert {t.name: t.count for t in bag.summary().topics} == {
            "vehicle_local_position": COUNTS["vehicle_local_position"],
            "logged_messages": len(fp.PX4_TEXTS) + 1,
            "sensor_accel/1": 41,
        }
        assert {c.encoding for c in bag.connections} == {Encoding.JSON}
        assert bag.topic_connections("vehicle_local_position")[0].msgtype == "px4/vehicle_local_position"
    for topic, fields in (("vehicle_local_position", ("x", "y", "z", "heading")), ("sensor_accel/1", ("name",))):
        before, after = _everything(source, topic), _everything(copy, topic)
        assert [t for t, _ in after] == [t for t, _ in before]
        for (_, old), (_, new) in zip(before, after, strict=True):
            assert [getattr(new, f) for f in fields] == pytest.approx([getattr(old, f) for f in fields])
    accel = _everything(copy, "sensor_accel/1")[3][1]
    assert accel.samples[1].y == pytest.approx(-1.5)  # type: ignore[attr-defined]  # nested arrays survive


def test_dataflash_mode_names_travel_with_the_copy(tmp_path: Path) -> None:
    copy = _copy(write_dataflash(tmp_path / "log.bin"), tmp_path, FilterSpec(include_topics=("MODE", "GPS")))
    with open_bag(copy) as bag:
        names = [c.name for c in mode_changes(bag, "MODE")]
    assert names == [m[4] for m in fp.MODES]


def test_protobuf_mcap_copies_to_json_mcap_with_its_values(tmp_path: Path) -> None:
    copy = _copy(write_protobuf_mcap(tmp_path / "proto.mcap"), tmp_path, FilterSpec(start_ns=None))
    third = _everything(copy, "/pose")[3][1]
    assert (third.header.seq, third.x, third.ranges.tolist()) == (3, 0.3, [3.0, 4.0, 5.0])  # type: ignore[attr-defined]


def test_a_flight_log_cannot_be_written_as_a_ros_bag(tmp_path: Path) -> None:
    with pytest.raises(FilterError, match=r"not ROS messages.*write it as mcap-json"):
        _copy(write_ulog(tmp_path / "flight.ulg"), tmp_path, FilterSpec(), OutputFormat.ROS2_MCAP)
    assert not (tmp_path / "copy").exists()


def test_a_ros_bag_is_not_written_as_json_mcap(tmp_path: Path) -> None:
    with pytest.raises(FilterError, match="holds ROS messages only"):
        _copy(write_bag("ros1", tmp_path), tmp_path, FilterSpec(), OutputFormat.MCAP_JSON)
