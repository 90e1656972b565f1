"""Write a filtered copy of a bag: chosen topics, a time window, per-topic rate limits, any format.

Within one family (ROS 1 -> ROS 1, ROS 2 -> ROS 2) payloads are copied byte for byte with their
definitions, ROS 1 latching/callerid and ROS 2 QoS. Across families they are converted with
rosbags' byte-level converters and the definitions are generated for the target family.
The source's compression is kept within its format and replaced by the output format's usual
one across formats (see writer_storage). The output is all or nothing: a failure or a
cancellation removes what was written.
"""

from __future__ import annotations

import math
import shutil
import sqlite3
import struct
from collections.abc import Callable, Iterable, Iterator
from contextlib import contextmanager, suppress
from dataclasses import dataclass
from pathlib import Path

from rosbags.interfaces import Connection as RbConnection
from rosbags.rosbag1 import Writer as Ros1Writer
from rosbags.rosbag1 import WriterError as Ros1WriterError
from rosbags.rosbag2 import WriterError as Ros2WriterError

from bagmcp_shared.bags.models import BagFormat, Compression, Connection, Encoding
from bagmcp_shared.bags.reader import BagReader
from bagmcp_shared.bags.writer_connections import Convert, OutConn, ros1_output, ros2_output
from bagmcp_shared.bags.writer_connections import FilterError as FilterError
from bagmcp_shared.bags.writer_json_mcap import JsonMcapWriter, json_output
from bagmcp_shared.bags.writer_storage import AnyWriter, new_writer, output_compression
from bagmcp_shared.bags.writer_storage import OutputFormat as OutputFormat
from bagmcp_shared.errors import JobCancelledError

_PROGRESS_EVERY = 1000  # messages between progress reports (fewer for small selections)
_WRITE_ERRORS = (Ros1WriterError, Ros2WriterError, sqlite3.Error, OSError, struct.error)
Progress = Callable[[float, str], None]


class FilterCancelled(JobCancelledError):  # noqa: N818 (a cancellation, not an error; name is the API)
    """The caller cancelled writing a filtered bag; nothing was left on disk."""


def default_output(fmt: BagFormat, connections: Iterable[Connection] = ()) -> OutputFormat:
    """The output format closest to the input; a bare MCAP whose channels are all ROS 1 gives ROS 1; a
    recording with messages that are not ROS messages gives JSON MCAP."""
    encodings = {c.encoding for c in connections}
    if fmt.is_flight_log or any(not e.is_ros for e in encodings):
        return OutputFormat.MCAP_JSON
    if fmt is BagFormat.ROS1:
        return OutputFormat.ROS1
    if fmt is BagFormat.ROS2_SQLITE3:
        return OutputFormat.ROS2_SQLITE3
    if fmt is BagFormat.MCAP and encodings == {Encoding.ROS1}:
        return OutputFormat.ROS1
    return OutputFormat.ROS2_MCAP


@dataclass(frozen=True)
class FilterSpec:
    """Which messages to copy. Topic names match with or without their leading slash.

    ``include_topics`` None selects every topic; ``exclude_topics`` is applied after it.
    ``start_ns``/``end_ns`` are inclusive log times. ``rates_hz`` caps topics: a message is kept
    when at least 1/rate s passed since the last kept message of its topic.
    """

    include_topics: tuple[str, ...] | None = None
    exclude_topics: tuple[str, ...] = ()
    start_ns: int | None = None
    end_ns: int | None = None
    rates_hz: tuple[tuple[str, float], ...] = ()

    def __post_init__(self) -> None:
        if self.start_ns is not None and self.end_ns is not None and self.start_ns > self.end_ns:
            raise FilterError(f"the time window starts ({self.start_ns} ns) after it ends ({self.end_ns} ns)")
        for topic, rate in self.rates_hz:
            if not math.isfinite(rate) or rate <= 0:
                raise FilterError(f"the rate for {topic} must be a positive number of Hz, not {rate}")
        names = [t.lstrip("/") for t, _ in self.rates_hz]
        if len(set(names)) != len(names):
            raise FilterError("rates_hz names a topic more than once")


@dataclass(frozen=True)
class FilterResult:
    """The written bag (a .bag file or a ROS 2 directory), the messages written per topic, and its
    compression with a few words on how it relates to the source's ("bz2 chunks, as in the source")."""

    path: Path
    counts: dict[str, int]
    compression: Compression
    compression_note: str


@dataclass(frozen=True)
class _Stream:
    """How the messages of one source connection are written."""

    out: OutConn
    convert: Convert | None  # None copies the payload unchanged
    period_ns: float  # minimum spacing of kept messages; 0 keeps all


def write_filtered(
    reader: BagReader,
    directory: Path,
    name: str,
    *,
    fmt: OutputFormat,
    spec: FilterSpec,
    progress: Progress | None = None,
    cancelled: Callable[[], bool] | None = None,
) -> FilterResult:
    """Write the messages ``spec`` selects from ``reader`` as a new bag ``directory/name``.

    Raises TopicNotFoundError for unknown topics, FilterError for invalid requests and write
    failures, FilterCancelled when ``cancelled()`` turns true; no partial output is left behind.
    """
    target = _target_path(directory, name, fmt)
    streams = _plan(reader, spec, fmt)
    compression, note = output_compression(reader.format, reader.compression, fmt)
    topics = sorted({c.topic for c in reader.connections if c.id in streams})
    total = sum(c.count for c in reader.connections if c.id in streams)
    tracker = _Tracker(total, progress, cancelled)
    writer = _open_writer(target, fmt, compression)
    try:
        with _write_errors(writer):
            counts = _copy(reader, writer, spec, streams, topics, tracker)
            writer.close()
    except BaseException:
        with suppress(Exception):
            writer.abort()
        _remove(target)
        raise
    tracker.finish(f"wrote {sum(counts.values())} messages to {target.name} ({note})")
    return FilterResult(target, counts, compression, note)


def _target_path(directory: Path, name: str, fmt: OutputFormat) -> Path:
    """``directory/name.bag`` or the ROS 2 directory ``directory/name``; must not exist yet."""
    if not name or name in (".", "..") or any(ch in name for ch in "/\\\0"):
        raise FilterError(f"{name!r} is not a valid bag name (a plain file name is needed)")
    if not directory.is_dir():
        raise FilterError(f"{directory}: the output directory does not exist")
    suffix = {OutputFormat.ROS1: ".bag", OutputFormat.MCAP_JSON: ".mcap"}.get(fmt, "")
    target = directory / f"{name}{suffix}"
    if target.exists() or target.is_symlink():
        raise FilterError(f"{target} exists already; choose another name")
    return target


def _remove(target: Path) -> None:
    """Delete a partial output file or directory."""
    if target.is_dir() and not target.is_symlink():
        shutil.rmtree(target, ignore_errors=True)
    else:
        target.unlink(missing_ok=True)


# Selection -------------------------------------------------------------------------------------


def _select(reader: BagReader, spec: FilterSpec) -> list[Connection]:
    """Connections of the included topics minus the excluded ones, in bag order."""
    if spec.include_topics is None:
        chosen = {c.id for c in reader.connections}
    else:
        chosen = {c.id for t in spec.include_topics for c in reader.topic_connections(t)}
    dropped = {c.id for t in spec.exclude_topics for c in reader.topic_connections(t)}
    return [c for c in reader.connections if c.id in chosen - dropped]


def _periods(reader: BagReader, spec: FilterSpec, selected: list[Connection]) -> dict[str, float]:
    """Topic name -> minimum spacing (ns) of kept messages, for the rate-limited topics."""
    names = {c.topic for c in selected}
    periods: dict[str, float] = {}
    for topic, rate in spec.rates_hz:
        real = reader.topic_connections(topic)[0].topic
        if real not in names:
            raise FilterError(f"a rate is given for {real}, but that topic is not selected")
        periods[real] = 1e9 / rate
    return periods


def _plan(reader: BagReader, spec: FilterSpec, fmt: OutputFormat) -> dict[int, _Stream]:
    """Source connection id -> how its messages are written."""
    selected = _select(reader, spec)
    periods = _periods(reader, spec, selected)
    if fmt is OutputFormat.MCAP_JSON and all(c.encoding.is_ros for c in reader.connections):
        raise FilterError(
            f"{reader.path.name} holds ROS messages only; write it as ros1, ros2-sqlite3 or ros2-mcap "
            "(mcap-json is for flight logs and MCAP with non-ROS messages)"
        )
    plan: dict[int, _Stream] = {}
    for conn in selected:
        convert: Convert | None
        if fmt is OutputFormat.MCAP_JSON:
            out, convert = json_output(reader, conn)
        elif not conn.encoding.is_ros:
            raise FilterError(
                f"{conn.topic} ({conn.msgtype}) holds {conn.encoding.value} messages, not ROS messages, so it cannot "
                f"be written as {fmt.value}; write it as mcap-json (MCAP with JSON messages)"
            )
        else:
            out, convert = ros1_output(reader, conn) if fmt is OutputFormat.ROS1 else ros2_output(reader, conn)
        plan[conn.id] = _Stream(out, convert, periods.get(conn.topic, 0.0))
    return plan


# Definitions and conversion --------------------------------------------------------------------


class _Tracker:
    """Reports progress and polls for cancellation every few messages."""

    def __init__(self, total: int, progress: Progress | None, cancelled: Callable[[], bool] | None) -> None:
        self.total = total
        self.done = 0
        self.step = max(1, min(_PROGRESS_EVERY, total // 20))
        self._progress = progress
        self._cancelled = cancelled

    def check(self) -> None:
        """Report progress; raise FilterCancelled when the caller asks to stop."""
        if self._cancelled is not None and self._cancelled():
            raise FilterCancelled(f"cancelled after {self.done} of {self.total} messages")
        if self._progress is not None:
            fraction = min(1.0, self.done / self.total) if self.total else 0.0
            self._progress(fraction, f"{self.done}/{self.total} messages")

    def tick(self) -> None:
        self.done += 1
        if self.done % self.step == 0:
            self.check()

    def finish(self, message: str) -> None:
        if self._progress is not None:
            self._progress(1.0, message)


def _open_writer(target: Path, fmt: OutputFormat, compression: Compression) -> AnyWriter:
    """Create the output atomically: a path that exists (even one that just appeared) is kept."""
    try:
        writer = new_writer(target, fmt, compression)
        writer.open()
    except (Ros1WriterError, Ros2WriterError, FileExistsError) as err:  # rosbags refuses to overwrite anything
        raise FilterError(f"{target} exists already; choose another name") from err
    except _WRITE_ERRORS as err:  # created, then the storage could not be set up
        _remove(target)
        raise FilterError(f"{target}: the filtered bag could not be created ({err})") from err
    return writer


def _add(writer: AnyWriter, out: OutConn) -> RbConnection | int:
    if isinstance(writer, JsonMcapWriter):
        return writer.add_connection(out)
    if isinstance(writer, Ros1Writer):
        return writer.add_connection(
            out.topic,
            out.msgtype,
            msgdef=out.msgdef,
            md5sum=out.digest,
            callerid=out.callerid,
            latching=out.latching,
        )
    return writer.add_connection(
        out.topic, out.msgtype, msgdef=out.msgdef, rihs01=out.digest, offered_qos_profiles=out.qos
    )


def _put(writer: AnyWriter, target: RbConnection | int, log_time_ns: int, data: bytes | memoryview) -> None:
    if isinstance(writer, JsonMcapWriter):
        assert isinstance(target, int)
        writer.write(target, log_time_ns, data)
    else:
        assert isinstance(target, RbConnection)
        writer.write(target, log_time_ns, data)


@contextmanager
def _write_errors(writer: AnyWriter) -> Iterator[None]:
    """Third-party write errors become FilterError."""
    try:
        yield
    except _WRITE_ERRORS as err:
        raise FilterError(f"{writer.path}: the filtered bag could not be written ({err})") from err


def _copy(
    reader: BagReader,
    writer: AnyWriter,
    spec: FilterSpec,
    streams: dict[int, _Stream],
    topics: list[str],
    tracker: _Tracker,
) -> dict[str, int]:
    """Copy messages in log-time order; returns the count written per topic."""
    outputs: dict[OutConn, RbConnection | int] = {}
    for stream in streams.values():
        if stream.out not in outputs:
            outputs[stream.out] = _add(writer, stream.out)
    counts = dict.fromkeys(topics, 0)
    last_kept: dict[str, int] = {}
    stop_ns = None if spec.end_ns is None else spec.end_ns + 1
    tracker.check()
    for raw in reader.messages(topics, start_ns=spec.start_ns, stop_ns=stop_ns):
        stream = streams[raw.connection.id]
        topic = raw.connection.topic
        last = last_kept.get(topic)
        if last is None or raw.log_time_ns - last >= stream.period_ns:
            data = raw.data if stream.convert is None else stream.convert(raw.data)
            _put(writer, outputs[stream.out], raw.log_time_ns, data)
            last_kept[topic] = raw.log_time_ns
            counts[topic] += 1
        tracker.tick()
    tracker.check()
    return counts
