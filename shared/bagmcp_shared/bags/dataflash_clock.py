"""The time of every message of a DataFlash log, as pymavlink's DFReader gives it (``m._timestamp``).

pymavlink finds the clock when it opens a log: microsecond logs (``TimeUS`` first in most records) and
older millisecond logs (``TimeMS``; GPS records carry boot milliseconds in ``T``) are placed on UTC from
the first GPS record with a week number; without GPS the times stay "since boot". A record without a
time of its own (FMT, PARM in old logs) gets the time of the record before it in the file. Walking the
log with pymavlink costs about 30 us a record (2 s for a 3 MB log); for the two common clocks the same
times are computed here from the record offsets in about 50 ms. Other clocks (PX4-era DataFlash, GPS
interpolation) are walked with pymavlink.
"""

from __future__ import annotations

import struct
from collections.abc import Sequence

import numpy as np
import numpy.typing as npt
from pymavlink.DFReader import (  # type: ignore[import-untyped]
    DFReader_binary,
    DFReaderClock_msec,
    DFReaderClock_usec,
)

Offsets = npt.NDArray[np.int64]


def _first_field(data: npt.NDArray[np.uint8], offsets: Offsets, width: int) -> npt.NDArray[np.float64]:
    """The unsigned little-endian integer of ``width`` bytes right after each record's 3-byte header."""
    picks = data[(offsets + 3)[:, None] + np.arange(width)]
    values: npt.NDArray[np.float64] = picks.copy().view(f"<u{width}").reshape(-1).astype(np.float64)
    return values


def _own_times(
    reader: DFReader_binary, data: npt.NDArray[np.uint8], offsets: Offsets, types: Sequence[int]
) -> npt.NDArray[np.float64]:
    """Seconds from each record's own time field (the clock's timebase added); NaN where it has none.
    Millisecond ``TimeMS`` is marked with a negative sign to be checked against the running time."""
    clock = reader.clock
    own = np.full(len(offsets), np.nan)
    kinds = np.asarray(types)
    for mtype in np.unique(kinds).tolist():
        fmt = reader.formats[mtype]
        rows = np.flatnonzero(kinds == mtype)
        first = fmt.columns[0] if fmt.columns else ""
        if isinstance(clock, DFReaderClock_usec):
            if first == "TimeUS":
                own[rows] = clock.timebase + _first_field(data, offsets[rows], 8) * 0.000001
            elif first == "TimeMS" and not fmt.name.startswith(("ACC", "GYR")):
                own[rows] = -(clock.timebase + _first_field(data, offsets[rows], 4) * 0.001)
        elif first == "TimeMS":
            own[rows] = clock.timebase + _first_field(data, offsets[rows], 4) * 0.001
        elif fmt.name in ("GPS", "GPS2") and "T" in fmt.colhash:
            unpack = struct.Struct(fmt.msg_struct).unpack_from
            for row in rows.tolist():
                own[row] = clock.timebase + unpack(reader.data_map, int(offsets[row]) + 3)[fmt.colhash["T"]] * 0.001
    return own


def _start(reader: DFReader_binary) -> float:
    clock = reader.clock
    if isinstance(clock, DFReaderClock_usec) and clock.first_us_stamp is not None:
        return float(clock.timebase + clock.first_us_stamp * 0.000001)
    if isinstance(clock, DFReaderClock_msec) and clock.first_ms_stamp is not None:
        return float(clock.timebase + clock.first_ms_stamp * 0.001)
    return float(clock.timebase)


def _walked(reader: DFReader_binary, offsets: Offsets) -> npt.NDArray[np.float64]:
    reader._rewind(keep_messages=True)
    found: dict[int, float] = {}
    while (message := reader.recv_msg()) is not None:
        found[reader.offset - message.fmt.len] = float(message._timestamp)
    return np.asarray([found.get(int(o), np.nan) for o in offsets])


def record_times_s(reader: DFReader_binary, offsets: Offsets, types: Sequence[int]) -> npt.NDArray[np.float64]:
    """Epoch (or since-boot) seconds of the records at ``offsets`` (ascending), of the given types."""
    if not isinstance(reader.clock, DFReaderClock_usec | DFReaderClock_msec):
        return _walked(reader, offsets)
    data = np.frombuffer(reader.data_map, dtype=np.uint8)
    own = _own_times(reader, data, offsets, types)
    times = np.empty(len(offsets))
    now = _start(reader)
    for row, value in enumerate(own.tolist()):
        if value == value:  # not NaN
            if value >= 0:
                now = value
            elif -value >= now:
                now = -value
        times[row] = now
    return times
