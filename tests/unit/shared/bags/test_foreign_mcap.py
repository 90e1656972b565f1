"""MCAP whose messages are not ROS messages (JSON with and without a schema, protobuf) read through the
bag layer with typed field paths; what cannot be decoded is refused naming the encoding."""

from __future__ import annotations

from pathlib import Path

import pytest
from mcap.writer import Writer

from bagmcp_shared.bags import BagFormat, Encoding, open_bag
from bagmcp_shared.errors import UnsupportedFormatError
from bagmcp_shared.paths import field_paths
from tests.fixtures.foreign_mcap import COUNT, PERIOD_NS, START_NS, pose, write_json_mcap, write_protobuf_mcap


def test_json_channels_decode_with_the_schemas_types(tmp_path: Path) -> None:
    with open_bag(write_json_mcap(tmp_path / "json.mcap")) as bag:
        summary = bag.summary()
        conn = bag.topic_connections("/pose")[0]
        paths = dict(field_paths(bag.decoder.typestore(conn.msgtype), conn.msgtype))
        messages = [bag.decode(raw) for raw in bag.messages(["/pose"])]
    assert summary.format is BagFormat.MCAP
    assert (conn.encoding, conn.msgtype) == (Encoding.JSON, "robot/Pose2D")
    assert {t.name: t.count for t in summary.topics} == {"/pose": COUNT, "/status": COUNT}
    assert summary.start_ns == START_NS
    assert summary.end_ns == START_NS + (COUNT - 1) * PERIOD_NS
    assert paths == {
        "header.seq": "int64",
        "header.frame": "string",
        "x": "float64",
        "y": "float64",
        "ok": "bool",
        "ranges": "float64[]",
        "class_": "string",  # a Python keyword as a key gets a trailing underscore
    }
    seventh = messages[7]
    assert (seventh.header.seq, seventh.x, seventh.y, seventh.ok) == (7, 0.7, 1.4, False)  # type: ignore[attr-defined]
    assert seventh.ranges.tolist() == pose(7)["ranges"]  # type: ignore[attr-defined]


def test_a_json_channel_without_schema_takes_its_fields_from_the_first_message(tmp_path: Path) -> None:
    with open_bag(write_json_mcap(tmp_path / "json.mcap")) as bag:
        conn = bag.topic_connections("/status")[0]
        paths = dict(field_paths(bag.decoder.typestore(conn.msgtype), conn.msgtype))
        last = [bag.decode(raw) for raw in bag.messages(["/status"])][-1]
        notes = bag.summary().notes
    assert paths == {"battery": "int64", "mode": "string"}
    assert (last.battery, last.mode) == (100 - COUNT + 1, "auto")  # type: ignore[attr-defined]
    assert any("/status" in n and "first message" in n for n in notes)


def test_protobuf_channels_decode_with_the_descriptor_sets_types(tmp_path: Path) -> None:
    with open_bag(write_protobuf_mcap(tmp_path / "proto.mcap")) as bag:
        conn = bag.topic_connections("/pose")[0]
        paths = dict(field_paths(bag.decoder.typestore(conn.msgtype), conn.msgtype))
        third = [bag.decode(raw) for raw in bag.messages(["/pose"])][3]
    assert conn.encoding is Encoding.PROTOBUF
    assert paths == {
        "header.seq": "uint32",
        "header.frame": "string",
        "x": "float64",
        "y": "float64",
        "ok": "bool",
        "ranges": "float32[]",
        "blob": "uint8[]",
    }
    assert (third.header.seq, third.header.frame, third.x, third.y) == (3, "map", 0.3, 0.6)  # type: ignore[attr-defined]
    assert third.ranges.tolist() == [3.0, 4.0, 5.0]  # type: ignore[attr-defined]
    assert third.blob.tolist() == [3, 7]  # type: ignore[attr-defined]


def test_an_mcap_of_an_encoding_bagmcp_cannot_decode_is_refused_naming_it(tmp_path: Path) -> None:
    path = tmp_path / "cbor.mcap"
    with path.open("wb") as stream:
        writer = Writer(stream)
        writer.start(profile="", library="test")
        channel = writer.register_channel("/x", "cbor", 0)
        writer.add_message(channel, 1, b"\xa0", 1)
        writer.finish()  # type: ignore[no-untyped-call]
    with pytest.raises(UnsupportedFormatError, match="message encoding cbor cannot be decoded"):
        open_bag(path)
