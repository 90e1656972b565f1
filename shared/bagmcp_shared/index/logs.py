"""ROS log records (``rosgraph_msgs/Log``, ``rcl_interfaces/msg/Log``) as rows: built at ingest, or decoded."""

from __future__ import annotations

import json
from dataclasses import astuple, dataclass
from pathlib import Path
from typing import Protocol, cast

from bagmcp_shared.bags import BagReader
from bagmcp_shared.bags.counted import ReportProgress, counted
from bagmcp_shared.flight_types import FLIGHT_LOG_TYPES
from bagmcp_shared.index.flight_logs import flight_record
from bagmcp_shared.timebase import header_stamp_ns

LOG_TYPES = frozenset({"rosgraph_msgs/msg/Log", "rcl_interfaces/msg/Log"})
RECORD_TYPES = LOG_TYPES | FLIGHT_LOG_TYPES  # what analyze_logs reads: ROS logs and flight-log texts
MAX_TEXT = 2000


class _Stamp(Protocol):
    sec: int
    nanosec: int


class _Log(Protocol):
    level: int
    name: str
    msg: str
    file: str
    function: str
    line: int


@dataclass(frozen=True)
class LogRow:
    """One record: log time, the record's own stamp (0 when unset), raw level, node, text, source."""

    t_ns: int
    stamp_ns: int
    level: int
    node: str
    text: str
    file: str
    function: str
    line: int


def _stamp_ns(message: object) -> int:
    header = header_stamp_ns(message)
    if header is not None:
        return header
    stamp = getattr(message, "stamp", None)  # rcl_interfaces/msg/Log has a stamp, not a header
    if stamp is None:
        return 0
    own = cast(_Stamp, stamp)
    return int(own.sec) * 1_000_000_000 + int(own.nanosec)


def log_row(log_ns: int, message: object) -> LogRow:
    flight = flight_record(message)
    if flight is not None:
        level, node, text = flight
        return LogRow(
            t_ns=log_ns, stamp_ns=0, level=level, node=node, text=text[:MAX_TEXT], file="", function="", line=0
        )
    log = cast(_Log, message)
    return LogRow(
        t_ns=log_ns,
        stamp_ns=_stamp_ns(message),
        level=int(log.level),
        node=str(log.name),
        text=str(log.msg)[:MAX_TEXT],
        file=str(log.file),
        function=str(log.function),
        line=int(log.line),
    )


def decode_logs(reader: BagReader, topic: str, *, progress: ReportProgress | None = None) -> list[LogRow]:
    expected = sum(c.count for c in reader.topic_connections(topic))
    messages = counted(reader.messages([topic]), expected=expected, progress=progress, what=topic)
    return [log_row(raw.log_time_ns, reader.decode(raw)) for raw in messages]


def save_logs(rows: list[LogRow], path: Path) -> None:
    path.write_text(json.dumps([astuple(r) for r in rows], separators=(",", ":")))


def load_logs(path: Path) -> list[LogRow]:
    return [LogRow(*row) for row in json.loads(path.read_text())]
