"""The time model: what callers may pass in, and what every answer gives back.

Inputs: seconds from the bag start (numbers below 1e9), absolute epoch seconds (numbers at or
above 1e9), or ISO-8601 strings (UTC when no offset is given). Outputs give both the offset
from the bag start and the absolute stamp. Bags recorded in simulation time (stamps near 0)
are addressed by offset or ISO string, since their epoch numbers fall below 1e9.
"""

from __future__ import annotations

import math
from datetime import UTC, datetime

from pydantic import BaseModel, Field

from bagmcp_shared.errors import TimeError

EPOCH_THRESHOLD_S = 1e9
MAX_CLOCK_SKEW_NS = 60 * 10**9  # a header stamp further than this from log time is on another clock
MAX_EPOCH_S = 1e11  # the year 5138: anything larger is a mistake, not a time
TimeInput = float | int | str


def _parse_iso(text: str) -> int:
    try:
        moment = datetime.fromisoformat(text.strip().replace("z", "Z"))
    except ValueError as err:
        raise TimeError(
            f"time {text!r} is neither a number of seconds nor an ISO-8601 timestamp "
            "(e.g. 12.5, 1585866235.1 or '2020-04-02T22:23:55Z')"
        ) from err
    if moment.tzinfo is None:
        moment = moment.replace(tzinfo=UTC)
    delta = moment - datetime(1970, 1, 1, tzinfo=UTC)
    return (delta.days * 86_400 + delta.seconds) * 1_000_000_000 + delta.microseconds * 1000


def parse_time(value: TimeInput, *, start_ns: int) -> int:
    """An absolute time in nanoseconds for ``value``, given the bag's start time."""
    if isinstance(value, bool):
        raise TimeError(f"time must be a number or an ISO-8601 string, not {value!r}")
    if isinstance(value, str):
        try:
            number = float(value)
        except ValueError:
            return _parse_iso(value)
    else:
        number = float(value)
    if not math.isfinite(number) or abs(number) > MAX_EPOCH_S:
        raise TimeError(f"time {value!r} is out of range; give seconds from the bag start, epoch seconds or ISO-8601")
    if abs(number) < EPOCH_THRESHOLD_S:
        return start_ns + round(number * 1e9)
    return round(number * 1e9)


def iso_from_ns(stamp_ns: int) -> str:
    """ISO-8601 UTC with microseconds, e.g. ``2020-04-02T22:23:55.112411Z``."""
    seconds, nanos = divmod(stamp_ns, 1_000_000_000)
    moment = datetime.fromtimestamp(seconds, tz=UTC).replace(microsecond=nanos // 1000)
    return moment.isoformat().replace("+00:00", "Z")


class Instant(BaseModel):
    """One instant as every answer reports it: seconds from the bag start, epoch seconds, ISO-8601 UTC."""

    offset_s: float = Field(description="seconds from the bag start")
    stamp_s: float = Field(description="epoch seconds")
    iso: str

    @classmethod
    def of(cls, stamp_ns: int, *, start_ns: int) -> Instant:
        return cls(offset_s=round((stamp_ns - start_ns) / 1e9, 9), stamp_s=stamp_ns / 1e9, iso=iso_from_ns(stamp_ns))


def header_stamp_ns(message: object) -> int | None:
    """``header.stamp`` of a message in nanoseconds, or None when absent or zero."""
    stamp = getattr(getattr(message, "header", None), "stamp", None)
    sec, nanosec = getattr(stamp, "sec", None), getattr(stamp, "nanosec", None)
    if not isinstance(sec, int) or not isinstance(nanosec, int):
        return None
    total = sec * 1_000_000_000 + nanosec
    return total if total > 0 else None
