"""Time series of one topic: aligned log times, header stamps and columns, from the index or decoded."""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from bagmcp_shared.bags import BagReader, RawMessage
from bagmcp_shared.bags.counted import ReportProgress, counted
from bagmcp_shared.index.columns import column_getter
from bagmcp_shared.timebase import header_stamp_ns


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


class Collector:
    """Accumulates columns of one topic, one decoded message at a time."""

    def __init__(self, reader: BagReader, topic: str, columns: Iterable[str]) -> None:
        msgtype = reader.topic_connections(topic)[0].msgtype
        self.names = list(columns)
        self._getters = [column_getter(reader, msgtype, c) for c in self.names]
        self._times: list[int] = []
        self._headers: list[int] = []
        self._values: list[list[float | int | str | None]] = [[] for _ in self.names]

    def add(self, raw: RawMessage, message: object) -> None:
        row = [getter(message) for getter in self._getters]
        self._times.append(raw.log_time_ns)
        self._headers.append(header_stamp_ns(message) or 0)
        for column, value in zip(self._values, row, strict=True):
            column.append(value)

    def series(self, source: str) -> Series:
        arrays = {name: _array(column) for name, column in zip(self.names, self._values, strict=True)}
        times = np.asarray(self._times, dtype=np.int64)
        return Series(times, np.asarray(self._headers, dtype=np.int64), arrays, source)


def _array(values: list[float | int | str | None]) -> npt.NDArray[np.generic]:
    """One column as an array. A number a message lacks (None: JSON's null, which is how JSON writes NaN) is NaN,
    so the column stays numeric: an array of objects could not be read back from the index."""
    if None in values and all(v is None or isinstance(v, int | float | np.number) for v in values):
        return np.asarray([np.nan if v is None else v for v in values], dtype=np.float64)
    return np.asarray(values)


def decode_series(
    reader: BagReader,
    topic: str,
    columns: Iterable[str],
    *,
    start_ns: int | None = None,
    stop_ns: int | None = None,
    progress: ReportProgress | None = None,
) -> Series:
    """Decode ``topic`` and read ``columns`` of every message in the window (reporting progress)."""
    collector = Collector(reader, topic, columns)
    expected = sum(c.count for c in reader.topic_connections(topic))
    messages = reader.messages([topic], start_ns=start_ns, stop_ns=stop_ns)
    for raw in counted(messages, expected=expected, progress=progress, what=topic):
        collector.add(raw, reader.decode(raw))
    return collector.series("bag")


def header_rate_hz(header_ns: npt.NDArray[np.int64]) -> float | None:
    """Mean rate from header stamps when they are present and sane (all set, mostly increasing)."""
    if len(header_ns) < 2 or not (header_ns > 0).all():
        return None
    if float(np.mean(np.diff(header_ns) >= 0)) < 0.99:
        return None
    span = int(header_ns.max() - header_ns.min())
    return round((len(header_ns) - 1) * 1e9 / span, 4) if span > 0 else None
