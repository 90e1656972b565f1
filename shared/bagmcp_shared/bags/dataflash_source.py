"""ArduPilot DataFlash binary logs (.bin) through pymavlink's DFReader.

Each message type is a topic (``GPS``, ``ATT``, ``POS``, ``MODE``, ``MSG``, ``PARM``, ... and the
format records FMT/FMTU/UNIT/MULT), with pymavlink's counts: records cut off at the end of the file are
left out. Times are pymavlink's (see ``dataflash_clock``). pymavlink indexes the file when it opens
(about 0.1 s for a 3 MB log); payloads are read from its memory map when asked for. The MODE topic
carries the vehicle's mode names (pymavlink's table for the vehicle type the log's MSG/VER records give).
"""

from __future__ import annotations

import json
import mmap
from contextlib import suppress
from pathlib import Path

import numpy as np
from pymavlink import mavutil  # type: ignore[import-untyped]
from pymavlink.DFReader import DFReader_binary, DFReaderClock_msec, DFReaderClock_usec  # type: ignore[import-untyped]

from bagmcp_shared.bags.dataflash_clock import record_times_s
from bagmcp_shared.bags.dataflash_types import PREFIX, definition_json
from bagmcp_shared.bags.models import MODE_NAMES, Connection, Encoding
from bagmcp_shared.bags.quiet import library_output, printed_note
from bagmcp_shared.bags.table_source import Stream, TableSource
from bagmcp_shared.errors import DamagedBagError

MAX_TIME_S = 9e9  # nanoseconds past this do not fit in 64 bits (the year 2255)


def _open(path: Path) -> DFReader_binary:
    try:
        return DFReader_binary(str(path), zero_time_base=False)
    except Exception as err:  # pymavlink raises assertion, struct and its own errors on bad bytes
        _close_half_made(err)
        detail = str(err).strip().splitlines()[0] if str(err).strip() else type(err).__name__
        raise DamagedBagError(
            f"{path}: the DataFlash log is damaged and cannot be read ({detail}); use an intact copy"
        ) from err


def _close_half_made(err: BaseException) -> None:
    """Close the file and map of a reader whose constructor failed after opening them: pymavlink does not,
    and the caller never gets the object (its frames in the traceback still hold it as ``self``)."""
    frame = err.__traceback__
    while frame is not None:
        made = frame.tb_frame.f_locals.get("self")
        if isinstance(made, DFReader_binary):
            if (handle := getattr(made, "filehandle", None)) is not None:
                handle.close()
            with suppress(BufferError):  # a view of the map may live on in the traceback: then it goes with it
                if (mapped := getattr(made, "data_map", None)) is not None:
                    mapped.close()
            return
        frame = frame.tb_next


def _records(reader: DFReader_binary) -> tuple[np.ndarray, np.ndarray]:
    """Offsets and types of every complete record of a known type, in file order."""
    offsets: list[int] = []
    types: list[int] = []
    for mtype, found in enumerate(reader.offsets):
        fmt = reader.formats.get(mtype)
        if fmt is None or not found:
            continue
        kept = [o for o in found if o + fmt.len <= reader.data_len]
        offsets += kept
        types += [mtype] * len(kept)
    order = np.argsort(np.asarray(offsets, dtype=np.int64), kind="stable")
    return np.asarray(offsets, dtype=np.int64)[order], np.asarray(types, dtype=np.int64)[order]


def _mode_names(reader: DFReader_binary) -> str:
    """pymavlink's mode names for the vehicle type (learnt from MSG/VER records while it indexed)."""
    mapping = mavutil.mode_mapping_bynumber(reader.mav_type) or {}
    return json.dumps({str(number): str(name) for number, name in mapping.items()})


def _connection(reader: DFReader_binary, number: int, mtype: int, count: int) -> Connection:
    fmt = reader.formats[mtype]
    units = list(fmt.units) if fmt.units else [""] * len(fmt.columns)
    meta = ((MODE_NAMES, _mode_names(reader)),) if fmt.name == "MODE" else ()
    return Connection(
        id=number,
        topic=fmt.name,
        msgtype=PREFIX + fmt.name,
        encoding=Encoding.DATAFLASH,
        definition=definition_json(fmt.name, fmt.format, list(fmt.columns), units),
        definition_format="dataflash",
        count=count,
        metadata=meta,
    )


def _notes(reader: DFReader_binary, dropped: int, printed: str) -> list[str]:
    clock = reader.clock
    field = (
        "TimeUS"
        if isinstance(clock, DFReaderClock_usec)
        else "TimeMS"
        if isinstance(clock, DFReaderClock_msec)
        else "GPS"
    )
    notes = [f"ArduPilot DataFlash log; message times from {field} (pymavlink's clock)"]
    if clock.timebase > 0:
        notes.append("times are UTC: pymavlink placed the log's boot clock on GPS time")
    else:
        notes.append("the log has no GPS time: times are seconds since the flight controller booted, not UTC")
    if dropped:
        notes.append(f"{dropped} records cut off at the end of the file were left out")
    said = printed_note(printed, library="pymavlink")
    return [*notes, said] if said else notes


def _index(path: Path) -> tuple[DFReader_binary, np.ndarray, np.ndarray, np.ndarray]:
    """pymavlink's reader, and the offsets, types and times (ns) of every record in file order."""
    reader = _open(path)
    try:
        offsets, types = _records(reader)
        if not len(offsets):
            raise DamagedBagError(f"{path}: the DataFlash log holds no complete record; use an intact copy")
        times_s = record_times_s(reader, offsets, types.tolist())
        timed = np.abs(times_s) < MAX_TIME_S  # not NaN (pymavlink's walk skipped it) nor a damaged time
        offsets, types = offsets[timed], types[timed]
        times_ns = np.round(times_s[timed] * 1e9).astype(np.int64)
    except DamagedBagError:
        reader.close()
        raise
    except Exception as err:
        reader.close()
        raise DamagedBagError(
            f"{path}: the DataFlash log's records are inconsistent ({err}); use an intact copy"
        ) from err
    return reader, offsets, types, times_ns


def open_dataflash(path: Path) -> TableSource:
    """A source over a DataFlash .bin log; DamagedBagError when pymavlink cannot index it."""
    with library_output() as printed:
        reader, offsets, types, times_ns = _index(path)
    data: mmap.mmap = reader.data_map
    streams: list[Stream] = []
    for number, mtype in enumerate(sorted(set(types.tolist())), start=1):
        rows = np.flatnonzero(types == mtype)
        order = rows[np.argsort(times_ns[rows], kind="stable")]
        starts, length = offsets[order], reader.formats[mtype].len

        def payload(i: int, starts: np.ndarray = starts, length: int = length) -> bytes:
            start = int(starts[i]) + 3
            return bytes(data[start : start + length - 3])

        streams.append(Stream(_connection(reader, number, mtype, len(order)), times_ns[order], payload))
    dropped = sum(len(o) for o in reader.offsets) - len(offsets)
    notes = _notes(reader, dropped, printed.getvalue())
    return TableSource(sorted(streams, key=lambda s: s.connection.topic), notes=notes, close=reader.close)
