"""Tests for per-scan minimum series: first approach within a distance and the downsampled profile."""

from __future__ import annotations

import math

import numpy as np
import pytest

from bagmcp_analysis.lidar.scan import first_within, minimum_profile

PERIOD_NS = 100_000_000  # 10 Hz


def approach_series() -> tuple[list[int], list[float]]:
    """Obstacle 5 m ahead closing at 0.5 m/s to 0.5 m at t = 9 s, then leaving at 0.5 m/s."""
    times = [k * PERIOD_NS for k in range(201)]
    ranges = [0.5 + 0.5 * abs(t / 1e9 - 9.0) for t in times]
    return times, ranges


def test_first_within_finds_the_crossing_within_one_scan_period() -> None:
    times, ranges = approach_series()
    approach = first_within(times, ranges, [math.radians(20.0)] * len(times), distance_m=1.5)
    assert approach is not None
    crossing_ns = 7_000_000_000  # 0.5 + 0.5 * (9 - t) = 1.5
    assert crossing_ns <= approach.t_ns <= crossing_ns + PERIOD_NS
    assert approach.index == approach.t_ns // PERIOD_NS
    assert approach.range_m < 1.5
    assert approach.bearing_deg == pytest.approx(20.0)
    assert approach.stays_s == pytest.approx(4.0, abs=0.1 + 1e-9)  # closer than 1.5 m from t = 7 s to t = 11 s
    assert approach.total_within_s == pytest.approx(4.0, abs=0.1 + 1e-9)
    assert (approach.until_end, approach.episodes) == (False, 1)


def test_episodes_gaps_and_missing_scans_are_counted() -> None:
    times = [k * 1_000_000_000 for k in range(7)]
    ranges = [3.0, 0.5, 0.6, 3.0, math.nan, 0.4, 0.3]
    approach = first_within(times, ranges, [0.0] * 7, distance_m=1.0)
    assert approach is not None
    assert (approach.index, approach.t_ns, approach.range_m) == (1, 1_000_000_000, 0.5)
    assert approach.stays_s == pytest.approx(2.0)
    assert approach.total_within_s == pytest.approx(4.0)  # scans 1, 2, 5 and the last (median period 1 s)
    assert (approach.episodes, approach.until_end) == (2, False)


def test_staying_close_until_the_end_is_reported() -> None:
    approach = first_within([0, 500_000_000, 1_000_000_000], [2.0, 0.5, 0.4], [0.0, 0.0, math.pi], distance_m=1.0)
    assert approach is not None
    assert (approach.stays_s, approach.until_end, approach.episodes) == (0.5, True, 1)
    assert approach.total_within_s == pytest.approx(1.0)


def test_never_closer_returns_none() -> None:
    assert first_within([0, 1], [2.0, math.nan], [0.0, math.nan], distance_m=1.0) is None


def test_unsorted_times_are_rejected() -> None:
    with pytest.raises(ValueError, match="sorted"):
        first_within([2, 1], [0.1, 0.1], [0.0, 0.0], distance_m=1.0)


def test_minimum_profile_keeps_bucket_minima_and_the_global_minimum() -> None:
    times = np.arange(1000, dtype=np.int64) * PERIOD_NS
    ranges = 2.0 + np.sin(np.arange(1000) / 37.0)
    ranges[613] = 0.05
    ranges[100:140] = np.nan
    out_t, out_r = minimum_profile(times, ranges, max_points=50)
    assert len(out_t) == len(out_r) == 50
    assert out_t == sorted(out_t)
    assert 613 * PERIOD_NS in out_t
    assert min(r for r in out_r if r is not None) == 0.05
    for k, (t, r) in enumerate(zip(out_t, out_r, strict=True)):
        bucket = ranges[k * 20 : (k + 1) * 20]
        if np.isnan(bucket).all():
            assert (r, t) == (None, k * 20 * PERIOD_NS)
            continue
        assert r == pytest.approx(float(np.nanmin(bucket)))
        assert ranges[t // PERIOD_NS] == r


def test_minimum_profile_returns_short_series_unchanged_with_none_for_missing() -> None:
    assert minimum_profile([0, 1, 2], [1.0, math.nan, 0.5]) == ([0, 1, 2], [1.0, None, 0.5])
