"""Plain data that describes a bag and its messages, independent of the on-disk format."""

from __future__ import annotations

from collections import Counter
from collections.abc import Iterable
from dataclasses import dataclass, field
from enum import StrEnum
from typing import NamedTuple


class BagFormat(StrEnum):
    """The container a bag was read from."""

    ROS1 = "ros1"  # ROS 1 .bag (format 2.0; plain, bz2 or lz4 chunks)
    ROS2_SQLITE3 = "ros2-sqlite3"  # ROS 2 bag directory or bare .db3 file(s)
    ROS2_MCAP = "ros2-mcap"  # ROS 2 bag directory whose storage files are MCAP
    MCAP = "mcap"  # a bare .mcap file (ros1/ros2 profiles, or JSON, protobuf and data_tamer channels)
    ULOG = "px4-ulog"  # a PX4 ULog flight log (.ulg)
    DATAFLASH = "ardupilot-dataflash"  # an ArduPilot DataFlash binary log (.bin)

    @property
    def is_flight_log(self) -> bool:
        """A flight controller's log: no ROS types, no TF, no lidar, no images."""
        return self in (BagFormat.ULOG, BagFormat.DATAFLASH)


class Compression(StrEnum):
    """How a bag's messages are compressed on disk."""

    NONE = "none"
    BZ2 = "bz2"  # ROS 1 chunks
    LZ4 = "lz4"  # ROS 1 or MCAP chunks (LZ4 frames)
    ZSTD = "zstd"  # MCAP chunks
    ZSTD_FILE = "zstd-file"  # ROS 2: each storage file compressed whole (compression_mode: file)
    ZSTD_MESSAGE = "zstd-message"  # ROS 2: each payload compressed (compression_mode: message)

    @property
    def label(self) -> str:
        """A few words for messages: "bz2 chunks", "zstd per message"."""
        if self is Compression.NONE:
            return "no compression"
        if self is Compression.ZSTD_FILE:
            return "zstd per storage file"
        if self is Compression.ZSTD_MESSAGE:
            return "zstd per message"
        return f"{self.value} chunks"

    @classmethod
    def of_chunks(cls, names: Iterable[str]) -> Compression:
        """The compression most chunks use ("" and "none" are uncompressed, unknown names ignored).

        Uncompressed chunks count only when no chunk is compressed; ties go to the first name in
        alphabetical order so the answer never depends on chunk order.
        """
        known = {c.value for c in (cls.BZ2, cls.LZ4, cls.ZSTD)}
        counts = Counter(name for name in names if name in known)
        if not counts:
            return cls.NONE
        return cls(min(counts, key=lambda name: (-counts[name], name)))


class Encoding(StrEnum):
    """How message payloads are serialized."""

    ROS1 = "ros1"
    CDR = "cdr"
    JSON = "json"  # MCAP JSON channels; also the records bagmcp derives (ULog logged strings, parameters)
    PROTOBUF = "protobuf"
    DATA_TAMER = "data_tamer"
    ULOG = "ulog"  # a ULog data message: packed little-endian fields of the log's own format
    DATAFLASH = "dataflash"  # a DataFlash record body: fields of its FMT, multipliers of pymavlink

    @property
    def is_ros(self) -> bool:
        return self in (Encoding.ROS1, Encoding.CDR)


@dataclass(frozen=True)
class Connection:
    """One stream of messages: a topic with one type and one definition.

    ``definition`` is the message definition stored in the bag ("" when the bag has none);
    ``definition_format`` is "msg", "idl" or "" accordingly. ``metadata`` carries what a
    writer needs to reproduce the stream (ROS 2 QoS profiles, ROS 1 latching, callerid).
    """

    id: int
    topic: str
    msgtype: str
    encoding: Encoding
    definition: str
    definition_format: str
    count: int
    digest: str = ""
    metadata: tuple[tuple[str, str], ...] = ()

    @property
    def latched(self) -> bool:
        """ROS 1 latching, or a ROS 2 publisher offering transient-local durability."""
        meta = dict(self.metadata)
        qos = meta.get("offered_qos_profiles", "").lower()
        return meta.get("latching") == "1" or "durability: 1" in qos or "transient_local" in qos


MODE_NAMES = "mode_names"  # metadata of a DataFlash MODE connection: its mode numbers' names (JSON)


class RawMessage(NamedTuple):
    """A serialized message as stored, with its log (receive) time."""

    connection: Connection
    log_time_ns: int
    data: bytes


@dataclass(frozen=True)
class TopicSummary:
    """Per-topic facts: type, message count and the log times of the first and last message."""

    name: str
    msgtype: str
    count: int
    first_ns: int | None
    last_ns: int | None

    @property
    def rate_hz(self) -> float | None:
        """Mean message rate over the topic's own span; None with fewer than two messages."""
        if self.count < 2 or self.first_ns is None or self.last_ns is None:
            return None
        span_ns = self.last_ns - self.first_ns
        return (self.count - 1) * 1e9 / span_ns if span_ns > 0 else None


@dataclass(frozen=True)
class BagSummary:
    """What ``bagmcp info`` prints and the catalog stores about one bag."""

    path: str
    format: BagFormat
    size_bytes: int
    files: tuple[str, ...]
    topics: tuple[TopicSummary, ...]
    profile: str = ""
    notes: tuple[str, ...] = field(default=())

    @property
    def message_count(self) -> int:
        return sum(t.count for t in self.topics)

    @property
    def start_ns(self) -> int | None:
        firsts = [t.first_ns for t in self.topics if t.first_ns is not None]
        return min(firsts) if firsts else None

    @property
    def end_ns(self) -> int | None:
        lasts = [t.last_ns for t in self.topics if t.last_ns is not None]
        return max(lasts) if lasts else None

    @property
    def duration_s(self) -> float:
        if self.start_ns is None or self.end_ns is None:
            return 0.0
        return (self.end_ns - self.start_ns) / 1e9

    def topic(self, name: str) -> TopicSummary | None:
        """The topic called ``name``; a leading slash is optional on either side."""
        wanted = name.lstrip("/")
        return next((t for t in self.topics if t.name.lstrip("/") == wanted), None)
