"""Tests of topic_timing with exact synthetic stamps."""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
import pytest

from bagmcp_analysis.timing import topic_timing

TEN_HZ_NS = 100_000_000


def _ten_hz(count: int, *, start_ns: int = 1_000_000_000) -> npt.NDArray[np.int64]:
    return start_ns + np.arange(count, dtype=np.int64) * TEN_HZ_NS


def test_perfect_clock_has_exact_rate_and_zero_jitter() -> None:
    timing = topic_timing(_ten_hz(51))
    assert timing.count == 51
    assert timing.duration_s == pytest.approx(5.0)
    assert timing.rate_hz == pytest.approx(10.0)
    assert timing.nominal_rate_hz == pytest.approx(10.0)
    assert timing.median_period_s == pytest.approx(0.1)
    assert timing.jitter_s == 0.0
    assert timing.jitter_p95_s == 0.0
    assert timing.min_period_s == timing.max_period_s == pytest.approx(0.1)
    assert (timing.gaps, timing.gap_count, timing.dropped_estimate) == ([], 0, 0)
    assert (timing.duplicates, timing.out_of_order) == (0, 0)
    assert timing.header is None


def test_three_dropped_messages_make_one_gap_of_four_tenths() -> None:
    stamps = np.delete(_ten_hz(40), [20, 21, 22])
    timing = topic_timing(stamps)
    assert timing.count == 37
    assert timing.gap_count == 1
    assert timing.dropped_estimate == 3
    (gap,) = timing.gaps
    assert gap.index == 19
    assert (gap.start_ns, gap.end_ns) == (int(stamps[19]), int(stamps[20]))
    assert gap.length_s == pytest.approx(0.4)
    assert gap.periods == pytest.approx(4.0)
    assert timing.nominal_rate_hz == pytest.approx(10.0)
    assert timing.rate_hz == pytest.approx(36 / 3.9)
    assert timing.max_period_s == pytest.approx(0.4)


def test_gaps_are_listed_largest_first_and_capped() -> None:
    stamps = np.delete(_ten_hz(100), [10, 11, 12, 40, 41, 42, 43, 44, 70, 71, 72, 73])
    timing = topic_timing(stamps, max_gaps=2)
    assert timing.gap_count == 3
    assert [gap.length_s for gap in timing.gaps] == pytest.approx([0.6, 0.5])
    assert timing.dropped_estimate == 3 + 5 + 4


def test_a_gap_must_be_longer_than_the_threshold() -> None:
    stamps = np.delete(_ten_hz(30), [10, 11])
    assert topic_timing(stamps).gap_count == 0
    lowered = topic_timing(stamps, gap_periods=2.5)
    assert (lowered.gap_count, lowered.dropped_estimate) == (1, 2)


def test_constant_header_delay_is_reported_exactly() -> None:
    header = _ten_hz(20)
    timing = topic_timing(header + 50_000_000, header)
    assert timing.header is not None
    assert timing.header.present_fraction == 1.0
    assert timing.header.rate_hz == pytest.approx(10.0)
    assert timing.header.monotonic is True
    for delay in (timing.header.delay_mean_s, timing.header.delay_median_s, timing.header.delay_p95_s):
        assert delay == pytest.approx(0.05)
    assert (timing.header.delay_min_s, timing.header.delay_max_s) == pytest.approx((0.05, 0.05))


def test_missing_and_backwards_header_stamps() -> None:
    log = _ten_hz(4)
    header = np.array([log[0] - 10_000_000, 0, log[2] - 30_000_000, log[0]], dtype=np.int64)
    header_timing = topic_timing(log, header).header
    assert header_timing is not None
    assert header_timing.present_fraction == pytest.approx(0.75)
    assert header_timing.monotonic is False
    assert header_timing.delay_min_s == pytest.approx(0.01)
    assert header_timing.delay_max_s == pytest.approx(0.3)
    assert header_timing.delay_median_s == pytest.approx(0.03)
    assert header_timing.rate_hz == pytest.approx(2 / 0.18)


def test_all_zero_header_stamps_mean_no_header() -> None:
    assert topic_timing(_ten_hz(5), np.zeros(5, dtype=np.int64)).header is None


def test_duplicates_and_out_of_order_stamps_are_counted() -> None:
    stamps = np.array([0, 100, 100, 300, 200, 400, 500], dtype=np.int64) * 1_000_000
    timing = topic_timing(stamps)
    assert (timing.duplicates, timing.out_of_order) == (1, 1)
    assert timing.median_period_s == pytest.approx(0.1)
    assert timing.gap_count == 0
    assert timing.min_period_s == pytest.approx(0.1)
    assert timing.rate_hz == pytest.approx(6 / 0.5)


def test_alternating_periods_have_jitter_of_half_their_difference() -> None:
    periods_ns = np.tile([90_000_000, 110_000_000], 10)
    stamps = np.concatenate(([0], np.cumsum(periods_ns)))
    timing = topic_timing(stamps)
    assert timing.jitter_s == pytest.approx(0.01)
    assert timing.jitter_p95_s == pytest.approx(0.01)
    assert timing.median_period_s == pytest.approx(0.1)


@pytest.mark.parametrize("count", [0, 1])
def test_fewer_than_two_messages_leave_rates_undefined(count: int) -> None:
    stamps = _ten_hz(count)
    timing = topic_timing(stamps, stamps)
    assert (timing.count, timing.duration_s, timing.rate_hz, timing.median_period_s) == (count, 0.0, None, None)
    assert (timing.nominal_rate_hz, timing.jitter_s, timing.min_period_s) == (None, None, None)
    assert (timing.gaps, timing.dropped_estimate) == ([], 0)
    if count:
        assert timing.header is not None
        assert timing.header.rate_hz is None
        assert timing.header.delay_mean_s == 0.0


def test_all_messages_at_one_instant_have_no_rate() -> None:
    timing = topic_timing(np.full(5, 7, dtype=np.int64))
    assert (timing.rate_hz, timing.median_period_s, timing.duplicates) == (None, None, 4)


def test_gap_threshold_must_exceed_one_period() -> None:
    with pytest.raises(ValueError, match="gap_periods"):
        topic_timing(_ten_hz(5), gap_periods=1.0)
