"""The columnar index: time series of common numeric message types, extracted once at ingest.

Stored as one uncompressed ``.npz`` per topic (numpy arrays keyed by column name) plus a JSON
manifest. Columns are named by message path (``pose.pose.position.x``) or, for derived values,
by a plain name (``min_range``). ``read_series`` answers from the index when it has every column
asked for and decodes the bag otherwise; both give the same arrays.
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from pathlib import Path
from typing import Protocol, cast

import numpy as np
import numpy.typing as npt

from bagmcp_shared.bags import BagReader, RawMessage
from bagmcp_shared.errors import BagmcpError
from bagmcp_shared.paths import check_steps, extract, parse_field_path
from bagmcp_shared.timebase import header_stamp_ns

MANIFEST = "manifest.json"
FORMAT_VERSION = 2  # bump when the files change; older indexes are then ignored and rebuilt
Getter = Callable[[object], float | int | str]

_XYZ = ("x", "y", "z")
_ANGLES = ("roll", "pitch", "yaw")


def _vec(prefix: str, names: Iterable[str] = _XYZ) -> tuple[str, ...]:
    return tuple(f"{prefix}.{n}" for n in names)


_POSE = (*_vec("position"), *_vec("orientation", _ANGLES))
_TWIST = (*_vec("linear"), *_vec("angular"))
_NUMBERS = (
    "Float32",
    "Float64",
    "Int8",
    "Int16",
    "Int32",
    "Int64",
    "UInt8",
    "UInt16",
    "UInt32",
    "UInt64",
    "Bool",
)
INDEXED_COLUMNS: dict[str, tuple[str, ...]] = {
    "nav_msgs/msg/Odometry": (*(f"pose.pose.{c}" for c in _POSE), *(f"twist.twist.{c}" for c in _TWIST)),
    "geometry_msgs/msg/Pose": _POSE,
    "geometry_msgs/msg/PoseStamped": tuple(f"pose.{c}" for c in _POSE),
    "geometry_msgs/msg/PoseWithCovarianceStamped": tuple(f"pose.pose.{c}" for c in _POSE),
    "geometry_msgs/msg/Twist": _TWIST,
    "geometry_msgs/msg/TwistStamped": tuple(f"twist.{c}" for c in _TWIST),
    "sensor_msgs/msg/Imu": (
        *_vec("orientation", _ANGLES),
        *_vec("angular_velocity"),
        *_vec("linear_acceleration"),
    ),
    "sensor_msgs/msg/NavSatFix": ("latitude", "longitude", "altitude", "status.status"),
    "sensor_msgs/msg/BatteryState": ("voltage", "current", "percentage"),
    "sensor_msgs/msg/LaserScan": ("min_range", "min_bearing"),
    "rosgraph_msgs/msg/Log": ("level",),
    "rcl_interfaces/msg/Log": ("level",),
    **{f"std_msgs/msg/{n}": ("data",) for n in _NUMBERS},
}


class _Scan(Protocol):
    ranges: npt.ArrayLike
    range_min: float
    range_max: float
    angle_min: float
    angle_increment: float


def scan_minimum(message: object) -> tuple[float, float]:
    """Closest valid range of a LaserScan and its bearing (rad); NaN when no beam is valid."""
    scan = cast(_Scan, message)
    ranges = np.asarray(scan.ranges, dtype=np.float64)
    low, high = float(scan.range_min), float(scan.range_max)
    valid = np.isfinite(ranges) & (ranges >= low) & (ranges <= high)
    if not valid.any():
        return math.nan, math.nan
    index = int(np.argmin(np.where(valid, ranges, np.inf)))
    return float(ranges[index]), float(scan.angle_min) + index * float(scan.angle_increment)


DERIVED: dict[str, Getter] = {
    "min_range": lambda m: scan_minimum(m)[0],
    "min_bearing": lambda m: scan_minimum(m)[1],
}


def column_getter(reader: BagReader, msgtype: str, column: str) -> Getter:
    """A function reading ``column`` from a decoded message; wrong paths raise MessagePathError."""
    if column in DERIVED and msgtype == "sensor_msgs/msg/LaserScan":
        return DERIVED[column]
    steps = parse_field_path(column)
    check_steps(reader.decoder.typestore(msgtype), msgtype, steps)
    return lambda message: extract(message, steps)  # type: ignore[return-value]


@dataclass(frozen=True)
class Series:
    """Aligned arrays: log times (ns), header stamps (ns, 0 when absent) and one array per column."""

    t_ns: npt.NDArray[np.int64]
    header_ns: npt.NDArray[np.int64]
    columns: dict[str, npt.NDArray[np.generic]]
    source: str  # "index" or "bag"

    def window(self, start_ns: int | None, stop_ns: int | None) -> Series:
        lo = 0 if start_ns is None else int(np.searchsorted(self.t_ns, start_ns, side="left"))
        hi = len(self.t_ns) if stop_ns is None else int(np.searchsorted(self.t_ns, stop_ns, side="left"))
        return Series(
            self.t_ns[lo:hi],
            self.header_ns[lo:hi],
            {k: v[lo:hi] for k, v in self.columns.items()},
            self.source,
        )


class _Collector:
    """Accumulates columns of one topic, one decoded message at a time."""

    def __init__(self, reader: BagReader, topic: str, columns: Iterable[str]) -> None:
        msgtype = reader.topic_connections(topic)[0].msgtype
        self.names = list(columns)
        self._getters = [column_getter(reader, msgtype, c) for c in self.names]
        self._times: list[int] = []
        self._headers: list[int] = []
        self._values: list[list[float | int | str]] = [[] for _ in self.names]

    def add(self, raw: RawMessage, message: object) -> None:
        row = [getter(message) for getter in self._getters]
        self._times.append(raw.log_time_ns)
        self._headers.append(header_stamp_ns(message) or 0)
        for column, value in zip(self._values, row, strict=True):
            column.append(value)

    def series(self, source: str) -> Series:
        arrays = {name: np.asarray(column) for name, column in zip(self.names, self._values, strict=True)}
        times = np.asarray(self._times, dtype=np.int64)
        return Series(times, np.asarray(self._headers, dtype=np.int64), arrays, source)


def decode_series(
    reader: BagReader, topic: str, columns: Iterable[str], *, start_ns: int | None = None, stop_ns: int | None = None
) -> Series:
    """Decode ``topic`` and read ``columns`` of every message in the window."""
    collector = _Collector(reader, topic, columns)
    for raw in reader.messages([topic], start_ns=start_ns, stop_ns=stop_ns):
        collector.add(raw, reader.decode(raw))
    return collector.series("bag")


def _slug(topic: str) -> str:
    return (topic.strip("/").replace("/", "__") or "_root") + ".npz"


def _collectors(reader: BagReader) -> dict[str, _Collector]:
    """One collector per topic whose type the index covers and whose definition fits it."""
    found: dict[str, _Collector] = {}
    for conn in reader.connections:
        if conn.msgtype in INDEXED_COLUMNS and conn.count and conn.msgtype not in reader.decoder.problems:
            try:
                found.setdefault(conn.topic, _Collector(reader, conn.topic, INDEXED_COLUMNS[conn.msgtype]))
            except BagmcpError:
                continue  # a same-named type with another definition: left to decoding
    return found


def header_rate_hz(header_ns: npt.NDArray[np.int64]) -> float | None:
    """Mean rate from header stamps when they are present and sane (all set, mostly increasing)."""
    if len(header_ns) < 2 or not (header_ns > 0).all():
        return None
    if float(np.mean(np.diff(header_ns) >= 0)) < 0.99:
        return None
    span = int(header_ns.max() - header_ns.min())
    return round((len(header_ns) - 1) * 1e9 / span, 4) if span > 0 else None


def build_index(
    reader: BagReader, directory: Path, progress: Callable[[float, str], None] | None = None
) -> dict[str, dict[str, object]]:
    """Extract the columns of every indexed topic into ``directory`` in one pass; returns the manifest.

    A topic with a message that does not decode is left out of the index (its questions are then
    answered by decoding, which reports the problem).
    """
    directory.mkdir(parents=True, exist_ok=True)
    collectors = _collectors(reader)
    skipped: dict[str, str] = {}
    total = max(sum(c.count for c in reader.connections if c.topic in collectors), 1)
    for number, raw in enumerate(reader.messages(list(collectors))):
        topic = raw.connection.topic
        if topic in skipped:
            continue
        try:
            collectors[topic].add(raw, reader.decode(raw))
        except BagmcpError as err:
            skipped[topic] = str(err)
        if progress is not None and number % 5000 == 0:
            progress(number / total, "indexing")
    manifest: dict[str, dict[str, object]] = {}
    for topic, collector in collectors.items():
        if topic in skipped:
            continue
        series = collector.series("index")
        columns = {f"c:{k}": v for k, v in series.columns.items()}
        cast(Callable[..., None], np.savez)(
            directory / _slug(topic), t_ns=series.t_ns, header_ns=series.header_ns, **columns
        )
        manifest[topic] = {
            "file": _slug(topic),
            "columns": collector.names,
            "count": len(series.t_ns),
            "header_rate_hz": header_rate_hz(series.header_ns),
        }
    document = {"version": FORMAT_VERSION, "topics": manifest, "skipped": skipped}
    (directory / MANIFEST).write_text(json.dumps(document, indent=1))
    return manifest


class ColumnIndex:
    """A built index on local disk."""

    def __init__(self, directory: Path, manifest: dict[str, dict[str, object]]) -> None:
        self._dir = directory
        self._manifest = manifest

    @classmethod
    def load(cls, directory: Path | None) -> ColumnIndex | None:
        """The index in ``directory``; None when there is none or it is of another format version."""
        if directory is None:
            return None
        try:
            document = json.loads((directory / MANIFEST).read_text())
        except (OSError, ValueError):
            return None
        if not isinstance(document, dict) or document.get("version") != FORMAT_VERSION:
            return None
        topics = document.get("topics")
        return cls(directory, topics) if isinstance(topics, dict) else None

    def header_rates(self) -> dict[str, float]:
        """Header-stamp rate of each indexed topic that has sane header stamps."""
        return {t: float(r) for t, e in self._manifest.items() if isinstance(r := e.get("header_rate_hz"), int | float)}

    def columns(self, topic: str) -> list[str]:
        entry = self._entry(topic)
        names = entry.get("columns") if entry else None
        return [str(n) for n in names] if isinstance(names, list) else []

    def _entry(self, topic: str) -> dict[str, object] | None:
        wanted = topic.lstrip("/")
        return next((e for t, e in self._manifest.items() if t.lstrip("/") == wanted), None)

    def has(self, topic: str, columns: Iterable[str]) -> bool:
        known = set(self.columns(topic))
        return bool(known) and all(c in known for c in columns)

    def read(
        self, topic: str, columns: Iterable[str], *, start_ns: int | None = None, stop_ns: int | None = None
    ) -> Series:
        entry = self._entry(topic)
        assert entry is not None
        with np.load(self._dir / str(entry["file"])) as data:
            series = Series(data["t_ns"], data["header_ns"], {c: data[f"c:{c}"] for c in columns}, "index")
        return series.window(start_ns, stop_ns)


def read_series(
    reader: BagReader,
    topic: str,
    columns: Iterable[str],
    *,
    index: ColumnIndex | None,
    start_ns: int | None = None,
    stop_ns: int | None = None,
) -> Series:
    """Columns of ``topic`` in a window: from the index when it has them all, else decoded."""
    names = list(columns)
    if index is not None and index.has(topic, names):
        return index.read(topic, names, start_ns=start_ns, stop_ns=stop_ns)
    return decode_series(reader, topic, names, start_ns=start_ns, stop_ns=stop_ns)
