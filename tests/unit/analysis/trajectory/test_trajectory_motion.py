"""Tests of speed windows, moving/stopped time and stops: batched and backwards stamps, turns in place."""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt
import pytest

from bagmcp_analysis.trajectory.track import Track, summarize_track
from tests.fixtures.synthetic_tracks import phased_track


def _batched_track(stamp_of_sample: npt.NDArray[np.int64]) -> Track:
    """1 m/s along x sampled at 100 Hz for 5 s, with the given (batched) stamps."""
    count = stamp_of_sample.size
    x = np.arange(count, dtype=np.float64) * 0.01
    return Track(t_ns=stamp_of_sample.astype(np.int64), x=x, y=np.zeros(count), z=np.zeros(count), yaw=np.zeros(count))


@pytest.mark.parametrize("convention", ["batch_start", "batch_end", "nearly_equal"])
def test_batched_log_stamps_do_not_inflate_speed(convention: str) -> None:
    sample = np.arange(501)
    batch = {"batch_start": sample // 10, "batch_end": (sample + 9) // 10, "nearly_equal": sample // 10}[convention]
    stamps = batch * 100_000_000 + (sample % 10 * 1_000 if convention == "nearly_equal" else 0)
    summary = summarize_track(_batched_track(stamps))
    assert summary.max_speed_mps == pytest.approx(1.0, rel=0.1)
    assert summary.distance_2d_m == pytest.approx(5.0)
    assert summary.stops == []
    assert summary.moving_s == pytest.approx(summary.duration_s)
    assert any(note.startswith("450 of 500 time steps repeat the previous stamp") for note in summary.notes)


def test_backwards_stamps_add_no_time_and_no_absurd_speed() -> None:
    stamps = np.arange(201, dtype=np.int64) * 10_000_000
    stamps[50] -= 30_000_000
    stamps[120] -= 15_000_000
    summary = summarize_track(_batched_track(stamps))
    assert summary.max_speed_mps == pytest.approx(1.0, rel=0.1)
    assert summary.duration_s == pytest.approx(2.0)
    assert any(note.startswith("0 of 200 time steps") and "and 2 go backwards" in note for note in summary.notes)


def test_all_poses_with_one_stamp_have_no_speed() -> None:
    track = Track(t_ns=np.full(5, 7), x=np.arange(5.0), y=np.zeros(5), z=np.zeros(5), yaw=np.zeros(5))
    summary = summarize_track(track)
    assert summary.distance_2d_m == pytest.approx(4.0)
    assert summary.duration_s == 0.0
    assert summary.max_speed_mps is None
    assert summary.mean_speed_mps is None
    assert any("share one timestamp" in note for note in summary.notes)


def test_rotation_in_place_counts_as_moving() -> None:
    summary = summarize_track(phased_track([(4.0, 0.0, 0.5)]))
    assert summary.distance_2d_m == pytest.approx(0.0, abs=1e-12)
    assert summary.path_efficiency is None
    assert summary.mean_moving_speed_mps == pytest.approx(0.0, abs=1e-12)
    assert summary.moving_s == pytest.approx(4.0)
    assert summary.stopped_s == pytest.approx(0.0)
    assert summary.stops == []


def test_slow_rotation_below_the_turn_rate_is_a_stop() -> None:
    summary = summarize_track(phased_track([(4.0, 0.0, 0.05)]))
    assert summary.stopped_s == pytest.approx(4.0)
    assert [(stop.start_index, stop.end_index) for stop in summary.stops] == [(0, 80)]


def test_pause_on_a_straight_drive_is_one_stop_of_the_right_length() -> None:
    summary = summarize_track(phased_track([(2.0, 1.0, 0.0), (2.0, 0.0, 0.0), (2.0, 1.0, 0.0)]))
    assert len(summary.stops) == 1
    stop = summary.stops[0]
    assert stop.duration_s == pytest.approx(2.0, abs=0.1)
    assert stop.start_index / 20 == pytest.approx(2.0, abs=0.1)
    assert stop.end_index / 20 == pytest.approx(4.0, abs=0.1)
    assert summary.moving_s == pytest.approx(4.0, abs=0.1)
    assert summary.mean_moving_speed_mps == pytest.approx(1.0, rel=0.03)
    assert [w.reason for w in summary.waypoints] == ["start", "end"]


def test_pauses_shorter_than_half_a_second_are_not_stops() -> None:
    summary = summarize_track(phased_track([(2.0, 1.0, 0.0), (0.3, 0.0, 0.0), (2.0, 1.0, 0.0)]))
    assert summary.stops == []
    assert summary.stopped_s == pytest.approx(0.3, abs=0.1)


def test_max_speed_index_points_into_the_fastest_stretch() -> None:
    summary = summarize_track(phased_track([(2.0, 0.5, 0.0), (2.0, 2.0, 0.0), (2.0, 0.5, 0.0)]))
    assert summary.max_speed_mps == pytest.approx(2.0)
    assert summary.max_speed_index is not None
    assert 2.0 <= summary.max_speed_index / 20 <= 4.0
    assert summary.distance_2d_m == pytest.approx(1.0 + 4.0 + 1.0)
    assert summary.mean_speed_mps == pytest.approx(6.0 / 6.0)


def test_unknown_heading_only_uses_linear_speed() -> None:
    base = phased_track([(2.0, 0.0, 1.0)])
    track = Track(t_ns=base.t_ns, x=base.x, y=base.y, z=base.z, yaw=np.full(base.x.size, math.nan))
    summary = summarize_track(track)
    assert summary.stopped_s == pytest.approx(2.0)


def _stall_then_burst(*, log_time: bool) -> Track:
    """0.5 m/s along x at 20 Hz for 10 s; on log time the recorder stalls 0.25 s at 5 s, then writes the five
    stalled messages within 2 ms (the nav2 TurtleBot's /odom in log time)."""
    sample = np.arange(201)
    stamps = sample * 50_000_000
    stalled = (sample > 100) & (sample <= 105)
    stamps[stalled] = 105 * 50_000_000 + (sample[stalled] - 101) * 400_000
    return Track(
        t_ns=stamps,
        x=sample.astype(np.float64) * 0.025,
        y=np.zeros(201),
        z=np.zeros(201),
        yaw=np.zeros(201),
        log_time=log_time,
    )


def test_a_stall_then_a_burst_on_log_time_is_not_a_speed_peak() -> None:
    summary = summarize_track(_stall_then_burst(log_time=True))
    assert summary.max_speed_mps == pytest.approx(0.5, rel=0.02)
    assert any("bunch up after stalls" in note for note in summary.notes)


def test_the_same_stamps_taken_as_sensor_stamps_keep_their_meaning() -> None:
    assert summarize_track(_stall_then_burst(log_time=False)).max_speed_mps > 1.0  # type: ignore[operator]
