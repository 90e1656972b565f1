"""Which clock a pose topic's speeds use: header stamps whenever they are consistent, whatever their offset."""

from __future__ import annotations

import numpy as np
import pytest

from bagmcp_analysis.queries.poses import pose_clock

LOG_NS = 1_778_234_353_000_000_000 + np.arange(100, dtype=np.int64) * 50_000_000


def test_a_simulation_clock_far_from_log_time_is_used_and_said() -> None:
    sim_ns = 936_000_000_000 + np.arange(100, dtype=np.int64) * 50_000_000
    stamps, clock, note = pose_clock(LOG_NS, sim_ns)
    assert clock == "header"
    assert stamps.tolist() == sim_ns.tolist()
    assert note is not None
    assert "another clock than log time" in note
    assert "936.000 s" in note


def test_header_stamps_near_log_time_need_no_note() -> None:
    stamps, clock, note = pose_clock(LOG_NS, LOG_NS - 3_000_000)
    assert (clock, note) == ("header", None)
    assert stamps[0] == LOG_NS[0] - 3_000_000


@pytest.mark.parametrize("header_step_ns", [0, 1_000])
def test_header_stamps_that_barely_advance_fall_back_to_log_time(header_step_ns: int) -> None:
    header = 5_000_000_000 + np.arange(100, dtype=np.int64) * header_step_ns
    stamps, clock, note = pose_clock(LOG_NS, header)
    assert clock == "log_time"
    assert stamps.tolist() == LOG_NS.tolist()
    assert note == "header stamps do not advance with log time, so log time was used"
