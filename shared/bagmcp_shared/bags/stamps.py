"""Log times and header stamps of a topic without decoding whole messages.

When a type's first field is ``std_msgs/Header`` the stamp sits at a fixed place in the serialized
bytes (after the 4-byte CDR encapsulation in ROS 2; after ``seq`` in ROS 1), so it is read directly;
other types are decoded.
"""

from __future__ import annotations

import struct
from collections.abc import Callable

import numpy as np
import numpy.typing as npt

from bagmcp_shared.bags.counted import ReportProgress, counted
from bagmcp_shared.bags.models import Connection, Encoding, RawMessage
from bagmcp_shared.bags.reader import BagReader
from bagmcp_shared.errors import BagmcpError
from bagmcp_shared.timebase import header_stamp_ns

HEADER = "std_msgs/msg/Header"
_STAMP = struct.Struct("<iI")
_STAMP_BE = struct.Struct(">iI")


def _fields(reader: BagReader, conn: Connection) -> list[tuple[str, tuple[object, object]]]:
    try:
        return list(reader.decoder.typestore(conn.msgtype).fielddefs[conn.msgtype][1])
    except BagmcpError:  # an undecodable type: no stamps
        return []


def _header_first(fields: list[tuple[str, tuple[object, object]]]) -> bool:
    return bool(fields) and fields[0][0] == "header" and fields[0][1][1] == HEADER


def _from_bytes(raw: RawMessage) -> int:
    data = raw.data
    if raw.connection.encoding is Encoding.CDR:
        little = len(data) > 1 and data[1] == 1
        sec, nanosec = (_STAMP if little else _STAMP_BE).unpack_from(data, 4)
    else:
        sec, nanosec = _STAMP.unpack_from(data, 4)
    stamp = sec * 1_000_000_000 + nanosec
    return stamp if stamp > 0 else 0


def stamp_reader(reader: BagReader, conn: Connection) -> Callable[[RawMessage], int] | None:
    """How to get a message's header stamp (0 when unset), or None when the type has no header."""
    fields = _fields(reader, conn)
    if _header_first(fields):
        return _from_bytes
    if "header" not in [name for name, _ in fields]:
        return None
    return lambda raw: header_stamp_ns(reader.decode(raw)) or 0


def topic_stamps(
    reader: BagReader,
    topic: str,
    *,
    start_ns: int | None = None,
    stop_ns: int | None = None,
    progress: ReportProgress | None = None,
) -> tuple[npt.NDArray[np.int64], npt.NDArray[np.int64] | None]:
    """Log times of ``topic`` and its header stamps (None when its type has no header)."""
    connections = reader.topic_connections(topic)
    readers = {c.id: stamp_reader(reader, c) for c in connections}
    times: list[int] = []
    stamps: list[int] = []
    messages = reader.messages([topic], start_ns=start_ns, stop_ns=stop_ns)
    expected = sum(c.count for c in connections)
    for raw in counted(messages, expected=expected, progress=progress, what=topic, every=10_000):
        times.append(raw.log_time_ns)
        read = readers.get(raw.connection.id)
        stamps.append(read(raw) if read is not None else 0)
    has_header = any(r is not None for r in readers.values())
    return np.asarray(times, dtype=np.int64), np.asarray(stamps, dtype=np.int64) if has_header else None
