"""write_filtered copies exactly the selected messages, keeps definitions/QoS/latching, converts
between ROS 1 and ROS 2, is deterministic and leaves nothing behind on failure or cancellation."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest
from rosbags.interfaces import Qos, QosDurability, QosHistory, QosLiveliness, QosReliability, QosTime
from rosbags.rosbag1 import Writer as Ros1Writer
from rosbags.rosbag2 import StoragePlugin
from rosbags.rosbag2 import Writer as Ros2Writer
from rosbags.rosbag2.metadata import parse_qos
from rosbags.typesys import Stores, get_typestore

from bagmcp_shared.bags import BagFormat, BagReader, Connection, Encoding, open_bag
from bagmcp_shared.bags.writer import (
    FilterCancelled,
    FilterError,
    FilterResult,
    FilterSpec,
    OutputFormat,
    default_output,
    write_filtered,
)
from bagmcp_shared.errors import TopicNotFoundError
from tests.fixtures import scenario as sc
from tests.fixtures.bagfactory import BagKind, make, scenario_typestore

ALL_FORMATS = tuple(f for f in OutputFormat if f is not OutputFormat.MCAP_JSON)  # the ROS formats
NATIVE: dict[BagFormat, OutputFormat] = {
    BagFormat.ROS1: OutputFormat.ROS1,
    BagFormat.ROS2_SQLITE3: OutputFormat.ROS2_SQLITE3,
    BagFormat.ROS2_MCAP: OutputFormat.ROS2_MCAP,
}


def _filter(
    source: Path, out_dir: Path, spec: FilterSpec, fmt: OutputFormat | None = None, name: str = "out"
) -> FilterResult:
    with open_bag(source) as bag:
        return write_filtered(bag, out_dir, name, fmt=fmt or NATIVE[bag.format], spec=spec)


def _counts(path: Path) -> dict[str, int]:
    with open_bag(path) as bag:
        return {t.name: t.count for t in bag.summary().topics}


def _values(msg: object) -> object:
    """A message as plain Python values; ROS 1's Header.seq (absent in ROS 2) is left out."""
    if dataclasses.is_dataclass(msg) and not isinstance(msg, type):
        return {
            f.name: _values(getattr(msg, f.name))
            for f in dataclasses.fields(msg)
            if not (f.name == "seq" and type(msg).__name__ == "std_msgs__msg__Header")
        }
    if isinstance(msg, np.ndarray):
        return msg.tolist()
    if isinstance(msg, list):
        return [_values(v) for v in msg]
    return msg


def _decoded(path: Path, topic: str) -> list[tuple[int, object]]:
    with open_bag(path) as bag:
        return [(raw.log_time_ns, _values(bag.decode(raw))) for raw in bag.messages([topic])]


def _files(path: Path) -> dict[str, bytes]:
    if path.is_file():
        return {path.name: path.read_bytes()}
    return {p.name: p.read_bytes() for p in sorted(path.iterdir())}


# Selection -------------------------------------------------------------------------------------


@pytest.mark.parametrize("fmt", ALL_FORMATS)
def test_included_topics_are_copied_whole_into_every_format(
    scenario_bag: Path, tmp_path: Path, fmt: OutputFormat
) -> None:
    spec = FilterSpec(include_topics=("/cmd_vel", "odom"))
    result = _filter(scenario_bag, tmp_path, spec, fmt)
    assert result.counts == {"/cmd_vel": 100, "/odom": 200}
    assert _counts(result.path) == {"/cmd_vel": 100, "/odom": 200}
    assert result.path == (tmp_path / "out.bag" if fmt is OutputFormat.ROS1 else tmp_path / "out")


def test_an_inclusive_window_keeps_both_ends_with_their_log_times(scenario_bag: Path, tmp_path: Path) -> None:
    spec = FilterSpec(include_topics=("/cmd_vel",), start_ns=sc.stamp_ns(2.0), end_ns=sc.stamp_ns(3.0))
    result = _filter(scenario_bag, tmp_path, spec)
    messages = _decoded(result.path, "/cmd_vel")
    assert result.counts == {"/cmd_vel": 11}
    assert [t for t, _ in messages] == [sc.stamp_ns(2.0 + i / 10) for i in range(11)]
    speeds = [msg["linear"]["x"] for _, msg in messages]  # type: ignore[index]
    assert speeds == pytest.approx([sc.cmd_speed_at(2.0)] * 10 + [sc.cmd_speed_at(3.0)])


def test_a_rate_limit_keeps_one_message_per_period(scenario_bag: Path, tmp_path: Path) -> None:
    spec = FilterSpec(include_topics=("/odom", "/cmd_vel"), rates_hz=(("odom", 5.0),))
    result = _filter(scenario_bag, tmp_path, spec)
    times = [t for t, _ in _decoded(result.path, "/odom")]
    assert result.counts == {"/cmd_vel": 100, "/odom": 50}
    assert times == [sc.stamp_ns(i * 0.2) for i in range(50)]
    assert set(np.diff(times).tolist()) == {200_000_000}


def test_excluded_topics_are_left_out(scenario_bag: Path, tmp_path: Path) -> None:
    spec = FilterSpec(exclude_topics=("/tf", "scan", "/camera/image_raw"))
    result = _filter(scenario_bag, tmp_path, spec)
    expected = {t: n for t, n in sc.COUNTS.items() if t not in ("/tf", "/scan", "/camera/image_raw")}
    assert result.counts == expected
    assert _counts(result.path) == expected


@pytest.mark.parametrize("fmt", ALL_FORMATS)
def test_a_window_without_messages_writes_a_valid_empty_bag(
    scenario_bag: Path, tmp_path: Path, fmt: OutputFormat
) -> None:
    after_end = sc.stamp_ns(sc.DURATION_S + 5)
    spec = FilterSpec(include_topics=("/odom", "/battery_level"), start_ns=after_end)
    result = _filter(scenario_bag, tmp_path, spec, fmt)
    assert result.counts == {"/battery_level": 0, "/odom": 0}
    with open_bag(result.path) as bag:
        assert {t.name: t.count for t in bag.summary().topics} == {"/battery_level": 0, "/odom": 0}
        assert list(bag.messages()) == []
        assert bag.decoder.problems == {}


def test_an_empty_include_list_writes_a_bag_without_topics(scenario_bag: Path, tmp_path: Path) -> None:
    result = _filter(scenario_bag, tmp_path, FilterSpec(include_topics=()))
    assert result.counts == {}
    assert _counts(result.path) == {}


# Definitions, latching and QoS -----------------------------------------------------------------


@pytest.mark.parametrize("fmt", ALL_FORMATS)
def test_every_message_decodes_to_the_source_values_in_every_format(
    scenario_bag: Path, tmp_path: Path, fmt: OutputFormat
) -> None:
    result = _filter(scenario_bag, tmp_path, FilterSpec(), fmt)
    assert result.counts == sc.COUNTS
    for topic in sc.COUNTS:
        assert _decoded(result.path, topic) == _decoded(scenario_bag, topic), topic


@pytest.mark.parametrize("fmt", ALL_FORMATS)
def test_the_custom_type_keeps_its_definition(scenario_bag: Path, tmp_path: Path, fmt: OutputFormat) -> None:
    result = _filter(scenario_bag, tmp_path, FilterSpec(include_topics=(sc.BATTERY_TOPIC,)), fmt)
    with open_bag(result.path) as bag:
        (conn,) = bag.connections
        assert conn.msgtype == sc.BATTERY_TYPE
        assert conn.definition.startswith("float32 percent\nstring label\nuint16[] cell_mv")
        assert bag.decoder.problems == {}
        levels = [bag.decode(raw) for raw in bag.messages()]
    assert [m.label for m in levels] == [f"pack-{i}" for i in range(20)]  # type: ignore[attr-defined]
    assert [m.cell_mv.tolist() for m in levels][:2] == [[3700, 3710], [3699, 3709]]  # type: ignore[attr-defined]


def test_same_family_copies_keep_the_stored_definitions(scenario_bag: Path, tmp_path: Path) -> None:
    result = _filter(scenario_bag, tmp_path, FilterSpec())
    with open_bag(scenario_bag) as src, open_bag(result.path) as out:
        before = {c.topic: (c.msgtype, c.definition, c.definition_format, c.digest) for c in src.connections}
        after = {c.topic: (c.msgtype, c.definition, c.definition_format, c.digest) for c in out.connections}
    assert after == before


def test_ros1_latching_is_kept_and_becomes_transient_local_in_ros2(
    scenario_bags: dict[BagKind, Path], tmp_path: Path
) -> None:
    spec = FilterSpec(include_topics=("/tf_static", "/tf"))
    ros1 = _filter(scenario_bags["ros1"], tmp_path, spec, OutputFormat.ROS1, name="r1")
    with open_bag(ros1.path) as bag:
        latching = {c.topic: dict(c.metadata)["latching"] for c in bag.connections}
    assert latching == {"/tf": "0", "/tf_static": "1"}
    ros2 = _filter(scenario_bags["ros1"], tmp_path, spec, OutputFormat.ROS2_MCAP, name="r2")
    with open_bag(ros2.path) as bag:
        qos = {c.topic: parse_qos(dict(c.metadata)["offered_qos_profiles"]) for c in bag.connections}
    assert qos["/tf"] == []
    assert [q.durability for q in qos["/tf_static"]] == [QosDurability.TRANSIENT_LOCAL]


def _qos(durability: QosDurability, reliability: QosReliability, depth: int) -> Qos:
    forever = QosTime(9223372036, 854775807)
    return Qos(
        QosHistory.KEEP_LAST,
        depth,
        reliability,
        durability,
        forever,
        forever,
        QosLiveliness.AUTOMATIC,
        forever,
        avoid_ros_namespace_conventions=False,
    )


STATIC_QOS = [_qos(QosDurability.TRANSIENT_LOCAL, QosReliability.RELIABLE, 1)]
SENSOR_QOS = [
    _qos(QosDurability.VOLATILE, QosReliability.BEST_EFFORT, 5),
    _qos(QosDurability.VOLATILE, QosReliability.RELIABLE, 10),
]


def _ros2_bag_with_qos(directory: Path, plugin: StoragePlugin) -> Path:
    """/tf_static transient local, /chatter with two offered profiles (two publishers)."""
    store = scenario_typestore(ros1=False)
    path = directory / f"qos-{plugin.name.lower()}"
    with Ros2Writer(path, version=9, storage_plugin=plugin) as writer:
        static = writer.add_connection(
            "/tf_static", "tf2_msgs/msg/TFMessage", typestore=store, offered_qos_profiles=STATIC_QOS
        )
        chatter = writer.add_connection(
            "/chatter", "std_msgs/msg/String", typestore=store, offered_qos_profiles=SENSOR_QOS
        )
        tf = make(store, "tf2_msgs/msg/TFMessage", transforms=[])
        writer.write(static, sc.START_NS, store.serialize_cdr(tf, "tf2_msgs/msg/TFMessage"))
        for i in range(3):
            text = make(store, "std_msgs/msg/String", data=f"hello {i}")
            writer.write(chatter, sc.START_NS + i, store.serialize_cdr(text, "std_msgs/msg/String"))
    return path


@pytest.mark.parametrize("plugin", [StoragePlugin.SQLITE3, StoragePlugin.MCAP])
@pytest.mark.parametrize("fmt", [OutputFormat.ROS2_SQLITE3, OutputFormat.ROS2_MCAP])
def test_ros2_qos_profiles_survive(tmp_path: Path, plugin: StoragePlugin, fmt: OutputFormat) -> None:
    source = _ros2_bag_with_qos(tmp_path, plugin)
    result = _filter(source, tmp_path, FilterSpec(), fmt)
    with open_bag(result.path) as bag:
        qos = {c.topic: parse_qos(dict(c.metadata)["offered_qos_profiles"]) for c in bag.connections}
    assert qos == {"/tf_static": STATIC_QOS, "/chatter": SENSOR_QOS}
    assert _decoded(result.path, "/chatter") == _decoded(source, "/chatter")


def test_transient_local_becomes_ros1_latching(tmp_path: Path) -> None:
    source = _ros2_bag_with_qos(tmp_path, StoragePlugin.MCAP)
    result = _filter(source, tmp_path, FilterSpec(), OutputFormat.ROS1)
    with open_bag(result.path) as bag:
        latching = {c.topic: dict(c.metadata)["latching"] for c in bag.connections}
    assert latching == {"/tf_static": "1", "/chatter": "0"}
    assert [m["data"] for _, m in _decoded(result.path, "/chatter")] == ["hello 0", "hello 1", "hello 2"]  # type: ignore[index]


# Cross-family conversion -----------------------------------------------------------------------


def test_ros1_to_ros2_mcap_gets_ros2_definitions_and_equal_values(
    scenario_bags: dict[BagKind, Path], tmp_path: Path
) -> None:
    source = scenario_bags["ros1"]
    result = _filter(source, tmp_path, FilterSpec(), OutputFormat.ROS2_MCAP)
    humble = get_typestore(Stores.ROS2_HUMBLE)
    with open_bag(result.path) as bag:
        assert bag.format is BagFormat.ROS2_MCAP
        assert {c.encoding for c in bag.connections} == {Encoding.CDR}
        odom = bag.topic_connections("/odom")[0]
        assert "uint32 seq" not in odom.definition
        assert odom.definition == humble.generate_msgdef("nav_msgs/msg/Odometry", ros_version=2)[0]
    for topic in (sc.ODOM_TOPIC, sc.SCAN_TOPIC, sc.TF_TOPIC, sc.BATTERY_TOPIC, sc.IMAGE_TOPIC):
        assert _decoded(result.path, topic) == _decoded(source, topic), topic


def test_ros2_sqlite3_to_ros1_gets_ros1_md5s_and_equal_values(
    scenario_bags: dict[BagKind, Path], tmp_path: Path
) -> None:
    source = scenario_bags["ros2-sqlite3"]
    result = _filter(source, tmp_path, FilterSpec(), OutputFormat.ROS1)
    noetic = get_typestore(Stores.ROS1_NOETIC)
    with open_bag(result.path) as bag:
        assert bag.format is BagFormat.ROS1
        digests = {c.topic: c.digest for c in bag.connections}
        first_odom = bag.decode(next(bag.messages(["/odom"])))
    for topic, msgtype in (("/odom", "nav_msgs/msg/Odometry"), ("/scan", "sensor_msgs/msg/LaserScan")):
        assert digests[topic] == noetic.generate_msgdef(msgtype)[1]
    assert first_odom.header.seq == 0  # type: ignore[attr-defined]
    for topic in sc.COUNTS:
        assert _decoded(result.path, topic) == _decoded(source, topic), topic


def _ros1_bag_with_a_broken_type(directory: Path) -> Path:
    path = directory / "broken.bag"
    store = scenario_typestore(ros1=True)
    with Ros1Writer(path) as writer:
        good = writer.add_connection("/cmd_vel", "geometry_msgs/msg/Twist", typestore=store)
        bad = writer.add_connection("/mystery", "acme_msgs/msg/Thing", msgdef="int32 x\n", md5sum="0" * 32)
        twist = make(store, "geometry_msgs/msg/Twist")
        writer.write(good, sc.START_NS, store.serialize_ros1(twist, "geometry_msgs/msg/Twist"))
        writer.write(bad, sc.START_NS + 1, b"\x01\x00\x00\x00")
    return path


def test_an_undecodable_type_copies_within_ros1_but_cannot_be_converted(tmp_path: Path) -> None:
    source = _ros1_bag_with_a_broken_type(tmp_path)
    copied = _filter(source, tmp_path, FilterSpec(), OutputFormat.ROS1, name="copy")
    assert copied.counts == {"/cmd_vel": 1, "/mystery": 1}
    with open_bag(copied.path) as bag:
        raws = list(bag.messages(["/mystery"]))
    assert [(r.connection.digest, r.data) for r in raws] == [("0" * 32, b"\x01\x00\x00\x00")]
    with pytest.raises(FilterError, match=r"/mystery \(acme_msgs/msg/Thing\)"):
        _filter(source, tmp_path, FilterSpec(), OutputFormat.ROS2_MCAP, name="converted")
    assert not (tmp_path / "converted").exists()
    ok = _filter(source, tmp_path, FilterSpec(exclude_topics=("/mystery",)), OutputFormat.ROS2_MCAP, name="ok")
    assert ok.counts == {"/cmd_vel": 1}


def _ros2_bag_with_unusable_definitions(directory: Path) -> Path:
    """/unknown has no definition and no standard type; /holder's definition uses an undefined type."""
    path = directory / "unusable"
    with Ros2Writer(path, version=9, storage_plugin=StoragePlugin.MCAP) as writer:
        unknown = writer.add_connection("/unknown", "acme_msgs/msg/Thing", msgdef="", rihs01="RIHS01_" + "1" * 64)
        holder = writer.add_connection(
            "/holder", "acme_msgs/msg/Holder", msgdef="Part[] parts\n", rihs01="RIHS01_" + "2" * 64
        )
        writer.write(unknown, sc.START_NS, UNKNOWN_PAYLOAD)
        writer.write(holder, sc.START_NS + 1, HOLDER_PAYLOAD)
    return path


UNKNOWN_PAYLOAD = b"\x00\x01\x00\x00\x2a\x00\x00\x00"
HOLDER_PAYLOAD = b"\x00\x01\x00\x00\x00\x00\x00\x00"


@pytest.mark.parametrize("fmt", [OutputFormat.ROS2_SQLITE3, OutputFormat.ROS2_MCAP])
def test_ros2_types_without_a_usable_definition_are_still_copied_byte_for_byte(
    tmp_path: Path, fmt: OutputFormat
) -> None:
    source = _ros2_bag_with_unusable_definitions(tmp_path)
    result = _filter(source, tmp_path, FilterSpec(), fmt)
    with open_bag(result.path) as bag:
        payloads = [(r.connection.topic, r.log_time_ns, r.data) for r in bag.messages()]
        definitions = {c.topic: c.definition for c in bag.connections}
        assert sorted(bag.decoder.problems) == ["acme_msgs/msg/Holder", "acme_msgs/msg/Thing"]
    assert payloads == [
        ("/unknown", sc.START_NS, UNKNOWN_PAYLOAD),
        ("/holder", sc.START_NS + 1, HOLDER_PAYLOAD),
    ]
    assert definitions == {"/unknown": "", "/holder": "Part[] parts\n"}


def test_ros2_types_without_a_usable_definition_cannot_become_ros1(tmp_path: Path) -> None:
    source = _ros2_bag_with_unusable_definitions(tmp_path)
    with pytest.raises(FilterError, match=r"/unknown \(acme_msgs/msg/Thing\) cannot be converted to ROS 1"):
        _filter(source, tmp_path, FilterSpec(include_topics=("/unknown",)), OutputFormat.ROS1)
    with pytest.raises(FilterError, match="uses acme_msgs/msg/Part, which it does not define"):
        _filter(source, tmp_path, FilterSpec(include_topics=("/holder",)), OutputFormat.ROS1)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["unusable"]


@pytest.mark.corpus
@pytest.mark.parametrize("fmt", [OutputFormat.ROS2_SQLITE3, OutputFormat.ROS2_MCAP])
def test_qos_recorded_by_real_rosbag2_survives(corpus: Path, tmp_path: Path, fmt: OutputFormat) -> None:
    source = corpus / "ros2_mcap/rosbag2_talker"
    with open_bag(source) as bag:
        before = {c.topic: parse_qos(dict(c.metadata)["offered_qos_profiles"]) for c in bag.connections}
    result = _filter(source, tmp_path, FilterSpec(), fmt)
    with open_bag(result.path) as bag:
        after = {c.topic: parse_qos(dict(c.metadata)["offered_qos_profiles"]) for c in bag.connections}
    assert after == before
    assert any(q.durability is QosDurability.TRANSIENT_LOCAL for qos in before.values() for q in qos)


# Determinism -----------------------------------------------------------------------------------


@pytest.mark.parametrize("fmt", ALL_FORMATS)
def test_the_same_request_writes_byte_identical_bags(scenario_bag: Path, tmp_path: Path, fmt: OutputFormat) -> None:
    spec = FilterSpec(exclude_topics=("/scan",), start_ns=sc.stamp_ns(1.0), rates_hz=(("/tf", 4.0),))
    first, second = tmp_path / "a", tmp_path / "b"
    first.mkdir()
    second.mkdir()
    one = _filter(scenario_bag, first, spec, fmt, name="same")
    two = _filter(scenario_bag, second, spec, fmt, name="same")
    assert one.counts == two.counts
    assert one.counts["/tf"] == 36
    assert _files(one.path) == _files(two.path)


# Errors, cancellation, progress ----------------------------------------------------------------


def test_an_unknown_topic_is_refused_before_anything_is_written(scenario_bag: Path, tmp_path: Path) -> None:
    with pytest.raises(TopicNotFoundError, match="/odometry"):
        _filter(scenario_bag, tmp_path, FilterSpec(include_topics=("/odometry",)))
    with pytest.raises(TopicNotFoundError):
        _filter(scenario_bag, tmp_path, FilterSpec(rates_hz=(("/nope", 1.0),)))
    assert list(tmp_path.iterdir()) == []


def test_invalid_rates_and_windows_are_refused(scenario_bag: Path, tmp_path: Path) -> None:
    with pytest.raises(FilterError, match="positive"):
        FilterSpec(rates_hz=(("/odom", 0.0),))
    with pytest.raises(FilterError, match="positive"):
        FilterSpec(rates_hz=(("/odom", float("nan")),))
    with pytest.raises(FilterError, match="after it ends"):
        FilterSpec(start_ns=2, end_ns=1)
    with pytest.raises(FilterError, match="not selected"):
        _filter(scenario_bag, tmp_path, FilterSpec(include_topics=("/tf",), rates_hz=(("/odom", 1.0),)))
    with pytest.raises(FilterError, match="not a valid bag name"):
        _filter(scenario_bag, tmp_path, FilterSpec(), name="../escape")
    assert list(tmp_path.iterdir()) == []


def test_an_existing_output_is_never_overwritten(scenario_bag: Path, tmp_path: Path) -> None:
    first = _filter(scenario_bag, tmp_path, FilterSpec(include_topics=("/odom",)))
    before = _files(first.path)
    with pytest.raises(FilterError, match="exists already"):
        _filter(scenario_bag, tmp_path, FilterSpec(include_topics=("/cmd_vel",)))
    assert _files(first.path) == before


@pytest.mark.parametrize("fmt", ALL_FORMATS)
def test_cancelling_midway_removes_the_partial_output(scenario_bag: Path, tmp_path: Path, fmt: OutputFormat) -> None:
    polls: list[int] = []
    reports: list[float] = []

    def cancelled() -> bool:
        polls.append(1)
        return len(polls) >= 4

    with open_bag(scenario_bag) as bag, pytest.raises(FilterCancelled):
        write_filtered(
            bag,
            tmp_path,
            "partial",
            fmt=fmt,
            spec=FilterSpec(),
            progress=lambda f, _m: reports.append(f),
            cancelled=cancelled,
        )
    assert len(polls) == 4
    assert 0 < reports[-1] < 1
    assert list(tmp_path.iterdir()) == []


def test_an_error_while_writing_removes_the_partial_output(scenario_bag: Path, tmp_path: Path) -> None:
    def progress(fraction: float, _message: str) -> None:
        if fraction > 0.5:
            raise RuntimeError("disk on fire")

    with open_bag(scenario_bag) as bag, pytest.raises(RuntimeError, match="disk on fire"):
        write_filtered(bag, tmp_path, "broken", fmt=NATIVE[bag.format], spec=FilterSpec(), progress=progress)
    assert list(tmp_path.iterdir()) == []


def test_progress_rises_to_one(scenario_bag: Path, tmp_path: Path) -> None:
    reports: list[tuple[float, str]] = []
    with open_bag(scenario_bag) as bag:
        fmt = NATIVE[bag.format]
        write_filtered(bag, tmp_path, "p", fmt=fmt, spec=FilterSpec(), progress=lambda f, m: reports.append((f, m)))
    fractions = [f for f, _ in reports]
    assert fractions == sorted(fractions)
    assert fractions[0] == 0.0
    assert fractions[-1] == 1.0
    assert len(reports) > 10
    assert "595 messages" in reports[-1][1]


# Output format choice --------------------------------------------------------------------------


def _conn(encoding: Encoding) -> Connection:
    return Connection(1, "/t", "std_msgs/msg/String", encoding, "", "", 0)


def test_the_default_output_matches_the_input() -> None:
    assert default_output(BagFormat.ROS1) is OutputFormat.ROS1
    assert default_output(BagFormat.ROS2_SQLITE3) is OutputFormat.ROS2_SQLITE3
    assert default_output(BagFormat.ROS2_MCAP) is OutputFormat.ROS2_MCAP
    assert default_output(BagFormat.MCAP) is OutputFormat.ROS2_MCAP
    assert default_output(BagFormat.MCAP, [_conn(Encoding.CDR)]) is OutputFormat.ROS2_MCAP
    assert default_output(BagFormat.MCAP, [_conn(Encoding.ROS1)]) is OutputFormat.ROS1


def test_a_reader_is_left_usable_after_filtering(scenario_bag: Path, tmp_path: Path) -> None:
    with open_bag(scenario_bag) as bag:
        assert isinstance(bag, BagReader)
        write_filtered(bag, tmp_path, "x", fmt=OutputFormat.ROS2_MCAP, spec=FilterSpec(include_topics=("/odom",)))
        assert sum(1 for _ in bag.messages(["/odom"])) == sc.COUNTS["/odom"]
