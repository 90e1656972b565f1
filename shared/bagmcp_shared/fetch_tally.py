"""Bytes fetched from the object store on behalf of one tool call, for the call's audit line.

The process-wide counters (``BlockCounters``, /metrics) say how much a service fetched in all; a tally says how
much one call did. It lives in a context variable: the call's task sets it, and the threads the call starts
(``anyio.to_thread`` copies the context) add to the same box. A call that waits for a block another call is
fetching counts nothing for it: the bytes are the other call's."""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from dataclasses import dataclass


@dataclass
class FetchTally:
    fetched_bytes: int = 0


_TALLY: ContextVar[FetchTally | None] = ContextVar("bagmcp_fetch_tally", default=None)


@contextmanager
def tallied() -> Iterator[FetchTally]:
    """Count what is fetched inside the block (this task and the threads it starts)."""
    tally = FetchTally()
    token = _TALLY.set(tally)
    try:
        yield tally
    finally:
        _TALLY.reset(token)


def count_fetched(size: int) -> None:
    """Add ``size`` bytes to the running call's tally, if a call is counting."""
    if (tally := _TALLY.get()) is not None:
        tally.fetched_bytes += size
