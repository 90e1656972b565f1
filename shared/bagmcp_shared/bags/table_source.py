"""Message streams held as tables: per connection, sorted log times and a way to fetch each payload.

Flight logs are read through once when opened (pyulog parses a whole ULog; pymavlink indexes a whole
DataFlash log), so their sources keep, per topic, the times in order and where each payload is; a topic
or a window is then a ``searchsorted`` away, and messages of several topics are merged by time.
"""

from __future__ import annotations

import heapq
from collections.abc import Callable, Collection, Iterator, Sequence
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from bagmcp_shared.bags.models import Compression, Connection, RawMessage
from bagmcp_shared.bags.source import ListedSource


@dataclass(frozen=True)
class Stream:
    """One connection's messages: ``t_ns`` ascending, ``payload(i)`` the bytes of the i-th."""

    connection: Connection
    t_ns: npt.NDArray[np.int64]
    payload: Callable[[int], bytes]


def packed_payloads(blob: bytes, itemsize: int) -> Callable[[int], bytes]:
    """Payloads stored back to back, ``itemsize`` bytes each."""
    return lambda i: blob[i * itemsize : (i + 1) * itemsize]


def listed_payloads(items: Sequence[bytes]) -> Callable[[int], bytes]:
    return lambda i: items[i]


class TableSource(ListedSource):
    """A MessageSource over streams (see ``source.MessageSource``)."""

    def __init__(
        self, streams: Sequence[Stream], *, notes: Sequence[str] = (), close: Callable[[], None] = lambda: None
    ):
        self._streams = {s.connection.id: s for s in streams}
        self._connections = [s.connection for s in streams]
        self._notes = list(notes)
        self._close = close

    @property
    def compression(self) -> Compression:
        return Compression.NONE

    def bounds(self, connection_id: int) -> tuple[int, int] | None:
        stream = self._streams.get(connection_id)
        if stream is None or not len(stream.t_ns):
            return None
        return int(stream.t_ns[0]), int(stream.t_ns[-1])

    def messages(
        self, connection_ids: Collection[int], *, start_ns: int | None, stop_ns: int | None
    ) -> Iterator[RawMessage]:
        chosen = [self._streams[i] for i in sorted(set(connection_ids)) if i in self._streams]
        return heapq.merge(*(_window(s, start_ns, stop_ns) for s in chosen), key=lambda m: m.log_time_ns)

    def close(self) -> None:
        self._close()


def _window(stream: Stream, start_ns: int | None, stop_ns: int | None) -> Iterator[RawMessage]:
    times = stream.t_ns
    lo = 0 if start_ns is None else int(np.searchsorted(times, start_ns, side="left"))
    hi = len(times) if stop_ns is None else int(np.searchsorted(times, stop_ns, side="left"))
    for i in range(lo, hi):
        yield RawMessage(stream.connection, int(times[i]), stream.payload(i))
