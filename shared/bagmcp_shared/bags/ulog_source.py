"""PX4 ULog flight logs (.ulg) through pyulog.

Topics follow pyulog: a message name with multi id 0 is the topic ``vehicle_local_position``, other
instances are ``sensor_accel/1``; counts are pyulog's. Two topics are added from the log's other records:
``logged_messages`` (the logged strings, tagged ones too; analyze_logs reads them with ROS level names)
and ``parameters`` (the initial values at the log start, then every change at its time).

Times: ULog timestamps are microseconds since boot. When the log has GPS time (``time_utc_usec`` of
``vehicle_gps_position`` or ``sensor_gps`` with a fix) every time is moved onto UTC by the median offset
between the two clocks; otherwise the times stay "since boot" and a note says so. pyulog parses the whole
file when it opens (about 0.5 s for a 3 MB log), handles dropouts and appended data sections; its warnings
become notes instead of reaching stdout (which carries MCP in stdio mode).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import numpy.typing as npt
from pyulog import ULog  # type: ignore[import-untyped]

from bagmcp_shared.bags.json_types import schema_text
from bagmcp_shared.bags.models import Connection, Encoding
from bagmcp_shared.bags.quiet import library_output, printed_note
from bagmcp_shared.bags.table_source import Stream, TableSource, listed_payloads, packed_payloads
from bagmcp_shared.bags.ulog_types import PREFIX, Format, definition_text
from bagmcp_shared.errors import DamagedBagError

LOGGED_TOPIC = "logged_messages"
PARAMETER_TOPIC = "parameters"
LOGGED_TYPE = f"{PREFIX}logged_message"
PARAMETER_TYPE = f"{PREFIX}parameter"
LEVEL_NAMES = ("EMERGENCY", "ALERT", "CRITICAL", "ERROR", "WARNING", "NOTICE", "INFO", "DEBUG")
_LOGGED_SCHEMA = schema_text(
    LOGGED_TYPE,
    {"timestamp": "integer", "log_level": "integer", "level": "string", "tag": "integer", "message": "string"},
)
_PARAMETER_SCHEMA = schema_text(
    PARAMETER_TYPE, {"timestamp": "integer", "name": "string", "value": "number", "initial": "boolean"}
)
_GPS_TOPICS = ("vehicle_gps_position", "sensor_gps")
_YEAR_2000_US = 946_684_800_000_000


def _parse(path: Path) -> tuple[ULog, str]:
    try:
        with library_output() as printed:
            ulog = ULog(str(path))
    except Exception as err:  # pyulog raises struct, index, value and its own errors on bad bytes
        detail = str(err).strip().splitlines()[0] if str(err).strip() else type(err).__name__
        raise DamagedBagError(
            f"{path}: the ULog file is damaged and cannot be read ({detail}); use an intact copy"
        ) from err
    return ulog, printed.getvalue()


def utc_offset_us(ulog: ULog) -> int | None:
    """UTC minus boot time (us), from GPS samples with a fix and a UTC time; None without GPS time."""
    for name in _GPS_TOPICS:
        for data in ulog.data_list:
            if data.name != name or "time_utc_usec" not in data.data:
                continue
            utc = data.data["time_utc_usec"].astype(np.int64)
            valid = utc > _YEAR_2000_US
            if "fix_type" in data.data:
                valid &= data.data["fix_type"] >= 2
            if valid.any():
                return int(np.median(utc[valid] - data.data["timestamp"].astype(np.int64)[valid]))
    return None


def _topic(data: ULog.Data) -> str:
    return data.name if data.multi_id == 0 else f"{data.name}/{data.multi_id}"


def _data_stream(number: int, data: ULog.Data, formats: dict[str, Format], offset_us: int, start_us: int) -> Stream:
    """A topic's samples by timestamp; a sample stamped before logging started (the last value published
    before it) is logged at the log's start, its own time stays in its ``timestamp`` field."""
    names = [f.field_name for f in data.field_data]
    table = np.empty(len(data.data["timestamp"]), dtype=np.dtype([(n, data.data[n].dtype) for n in names]))
    for name in names:
        table[name] = data.data[name]
    order = np.argsort(table["timestamp"], kind="stable")
    table = table[order]
    conn = Connection(
        id=number,
        topic=_topic(data),
        msgtype=PREFIX + data.name,
        encoding=Encoding.ULOG,
        definition=definition_text(data.name, formats),
        definition_format="ulog",
        count=len(table),
        metadata=(("multi_id", str(data.multi_id)),),
    )
    times = (np.maximum(table["timestamp"].astype(np.int64), start_us) + offset_us) * 1000
    return Stream(conn, times, packed_payloads(table.tobytes(), table.dtype.itemsize))


def _json_stream(
    number: int, topic: str, msgtype: str, schema: str, rows: list[dict[str, object]], offset_us: int, start_us: int
) -> Stream:
    rows = sorted(rows, key=lambda r: int(r["timestamp"]))  # type: ignore[call-overload]
    conn = Connection(number, topic, msgtype, Encoding.JSON, schema, "jsonschema", len(rows))
    stamps = [max(int(r["timestamp"]), start_us) for r in rows]  # type: ignore[call-overload]
    times: npt.NDArray[np.int64] = (np.asarray(stamps, dtype=np.int64) + offset_us) * 1000
    return Stream(conn, times, listed_payloads([json.dumps(r).encode() for r in rows]))


def _logged(ulog: ULog) -> list[dict[str, object]]:
    rows: list[dict[str, object]] = []
    for tagged in [None, *ulog.logged_messages_tagged.items()]:
        items = ulog.logged_messages if tagged is None else tagged[1]
        for m in items:
            level = m.log_level - 48 if 48 <= m.log_level <= 55 else m.log_level  # ASCII digits '0'..'7'
            name = LEVEL_NAMES[level] if 0 <= level < len(LEVEL_NAMES) else "UNKNOWN"
            tag = None if tagged is None else int(tagged[0])
            rows.append(
                {"timestamp": int(m.timestamp), "log_level": level, "level": name, "tag": tag, "message": m.message}
            )
    return rows


def _parameters(ulog: ULog) -> list[dict[str, object]]:
    start = int(ulog.start_timestamp)
    rows: list[dict[str, object]] = [
        {"timestamp": start, "name": name, "value": float(value), "initial": True}
        for name, value in sorted(ulog.initial_parameters.items())
    ]
    rows += [
        {"timestamp": int(t), "name": n, "value": float(v), "initial": False} for t, n, v in ulog.changed_parameters
    ]
    return rows


def _notes(ulog: ULog, offset_us: int | None, printed: str) -> list[str]:
    info = ulog.msg_info_dict
    system = ", ".join(f"{k} {info[k]}" for k in ("sys_name", "ver_hw", "ver_sw_branch") if k in info)
    notes = [f"PX4 ULog ({system or 'no system information'}; software {ulog.get_version_info_str() or 'unknown'})"]
    if offset_us is None:
        notes.append("the log has no GPS time: times are seconds since the flight controller booted, not UTC")
    else:
        notes.append("times are UTC, from the log's boot-time microseconds and the GPS clock")
    if ulog.dropouts:
        lost = sum(d.duration for d in ulog.dropouts)
        notes.append(f"{len(ulog.dropouts)} dropouts: the logger lost {lost} ms of data in all")
    if ulog.has_data_appended:
        notes.append("the log has appended data sections; they were read")
    said = printed_note(printed, library="pyulog")
    if said is not None:
        notes.append(said)
    elif ulog.file_corruption:
        notes.append("pyulog found corrupt data in the file and skipped it")
    initial, changed = len(ulog.initial_parameters), len(ulog.changed_parameters)
    notes.append(f"topic {PARAMETER_TOPIC}: {initial} initial values, {changed} changes")
    return notes


def open_ulog(path: Path) -> TableSource:
    """A source over a ULog file; DamagedBagError when pyulog cannot parse it."""
    ulog, printed = _parse(path)
    if not ulog.message_formats:
        raise DamagedBagError(
            f"{path}: the ULog file holds no message formats (cut off after its header?); use an intact copy"
        )
    formats = {name: list(fmt.fields) for name, fmt in ulog.message_formats.items()}
    offset = utc_offset_us(ulog)
    shift, start = offset or 0, int(ulog.start_timestamp)
    ordered = sorted(ulog.data_list, key=lambda d: (d.name, d.multi_id))
    streams = [_data_stream(n, d, formats, shift, start) for n, d in enumerate(ordered, start=1)]
    number = len(ordered)
    logged, parameters = _logged(ulog), _parameters(ulog)
    streams.append(_json_stream(number + 1, LOGGED_TOPIC, LOGGED_TYPE, _LOGGED_SCHEMA, logged, shift, start))
    streams.append(
        _json_stream(number + 2, PARAMETER_TOPIC, PARAMETER_TYPE, _PARAMETER_SCHEMA, parameters, shift, start)
    )
    return TableSource(streams, notes=_notes(ulog, offset, printed))
