"""Titles and legends lie inside the figure: long titles of paths, many series with long names, runs compared
(the cases users saw clipped: three drive paths, the Husky's velocity 50-150 s, three drives compared)."""

from __future__ import annotations

import numpy as np
import pytest

from bagmcp_plotting.drawing.fitting import texts_outside
from bagmcp_plotting.drawing.lines import Line
from bagmcp_plotting.drawing.timeseries import draw_overlay, draw_timeseries
from bagmcp_plotting.drawing.xy import draw_xy

T = np.linspace(0.0, 100.0, 200)
HUSKY = "/husky_velocity_controller/odom.twist.twist"
LONG_TITLE = (
    f"test1: {HUSKY}.linear.x, {HUSKY}.angular.z, /husky_velocity_controller/cmd_vel.linear.x, "
    "/imu/data.angular_velocity.z from 50.000 s to 150.000 s (2023-06-01T12:00:50Z .. 2023-06-01T12:02:30Z)"
)


def _line(label: str, unit: str | None, scale: float) -> Line:
    return Line(label, unit, T, scale * np.sin(T / 7.0))


@pytest.mark.parametrize("count", [1, 3, 8])
def test_a_long_title_and_many_long_series_stay_inside(count: int) -> None:
    units = ["m/s", "rad/s"]
    lines = [_line(f"{HUSKY}.component_{i}.x", units[i % 2], 1.0 + i % 2) for i in range(count)]
    figure = draw_timeseries(lines, style="line", title=LONG_TITLE)
    assert texts_outside(figure) == []


def test_one_unbroken_path_as_title_wraps_inside() -> None:
    figure = draw_timeseries([_line("v", "m/s", 1.0)], style="line", title="/" + "very_long_topic_name" * 12)
    assert texts_outside(figure) == []


def test_runs_compared_keep_their_title_and_legend_inside() -> None:
    runs = [_line(f"drive_{kind} {HUSKY}.linear.x", "m/s", 1.0) for kind in ("ros1", "db3", "mcap", "copy-2")]
    figure = draw_overlay(runs, title=LONG_TITLE, y_label="linear.x [m/s]", x_label="time from bag start [s]")
    assert texts_outside(figure) == []


def test_a_trajectory_with_a_long_title_stays_inside() -> None:
    figure = draw_xy(
        x=np.cos(T),
        y=np.sin(T),
        t_s=T,
        x_label="x [m]",
        y_label="y [m]",
        title=LONG_TITLE,
        equal_aspect=True,
        color_by_time=True,
        mark_ends=True,
    )
    assert texts_outside(figure) == []


def test_the_check_sees_a_clipped_text() -> None:
    figure = draw_timeseries([_line("v", "m/s", 1.0)], style="line", title="t")
    figure.text(0.9, 0.5, "runs off the right edge " * 3)
    assert texts_outside(figure) == ["runs off the right edge " * 3]
