"""The time model: relative seconds, epoch seconds and ISO-8601 in; offset and stamp out."""

from __future__ import annotations

import pytest

from bagmcp_shared.errors import TimeError
from bagmcp_shared.timebase import Instant, header_stamp_ns, iso_from_ns, parse_time

START = 1_585_866_235_112_411_371


def test_numbers_below_1e9_are_seconds_from_the_bag_start() -> None:
    assert parse_time(2.5, start_ns=START) == START + 2_500_000_000
    assert parse_time(0, start_ns=START) == START


def test_numbers_at_or_above_1e9_are_epoch_seconds() -> None:
    assert parse_time(1_585_866_237.5, start_ns=START) == 1_585_866_237_500_000_000


def test_numeric_strings_behave_like_numbers() -> None:
    assert parse_time("2.5", start_ns=START) == START + 2_500_000_000


def test_iso_strings_without_offset_are_utc_and_with_offset_are_converted() -> None:
    assert parse_time("2020-04-02T22:23:57Z", start_ns=START) == 1_585_866_237_000_000_000
    assert parse_time("2020-04-02T22:23:57", start_ns=START) == 1_585_866_237_000_000_000
    assert parse_time("2020-04-03T00:23:57+02:00", start_ns=START) == 1_585_866_237_000_000_000


@pytest.mark.parametrize("bad", ["yesterday", "nan", "inf", True])
def test_unparseable_times_raise_a_time_error_with_examples(bad: str | bool) -> None:
    with pytest.raises(TimeError):
        parse_time(bad, start_ns=START)


def test_an_instant_reports_offset_absolute_and_iso() -> None:
    stamp = Instant.of(START + 1_500_000_000, start_ns=START)
    assert stamp.offset_s == 1.5
    assert stamp.stamp_s == pytest.approx(1_585_866_236.612411371)
    assert stamp.iso == "2020-04-02T22:23:56.612411Z"


def test_iso_from_ns_keeps_microseconds() -> None:
    assert iso_from_ns(1_700_000_000_000_001_000) == "2023-11-14T22:13:20.000001Z"


class _Time:
    def __init__(self, sec: int, nanosec: int) -> None:
        self.sec, self.nanosec = sec, nanosec


class _Header:
    def __init__(self, stamp: _Time) -> None:
        self.stamp = stamp


class _Stamped:
    def __init__(self, sec: int, nanosec: int) -> None:
        self.header = _Header(_Time(sec, nanosec))


def test_header_stamp_is_read_when_present_and_nonzero() -> None:
    assert header_stamp_ns(_Stamped(10, 5)) == 10_000_000_005
    assert header_stamp_ns(_Stamped(0, 0)) is None
    assert header_stamp_ns(object()) is None


@pytest.mark.parametrize("value", [1e308, -1e308, "1e300", 2e11])
def test_absurd_times_are_refused_with_a_sentence_not_an_overflow(value: float | str) -> None:
    with pytest.raises(TimeError, match="out of range"):
        parse_time(value, start_ns=START)
