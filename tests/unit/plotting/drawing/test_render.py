"""Tests for bagmcp_plotting.drawing: the public entry points, rendered concurrently from threads."""

from __future__ import annotations

from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor

import numpy as np

from bagmcp_plotting.drawing import Line, render_histogram, render_scan, render_timeseries, render_xy, summary_of

T_S = np.linspace(0.0, 60.0, 20_000)


def jobs() -> list[Callable[[], bytes]]:
    speed = Line("speed", "m/s", T_S, np.sin(T_S))
    yaw = Line("yaw rate", "rad/s", T_S, 0.3 * np.cos(T_S))
    return [
        lambda: render_timeseries([speed, yaw], style="line", title="twin"),
        lambda: render_histogram(np.sin(T_S), bins=None, label="speed", unit="m/s", title="hist"),
        lambda: render_scan(angles_rad=T_S[:720] / 10.0, ranges_m=np.full(720, 4.0), title="scan", range_max_m=8.0),
        lambda: render_xy(
            x=np.cos(T_S),
            y=np.sin(T_S),
            t_s=T_S,
            x_label="x [m]",
            y_label="y [m]",
            title="xy",
            equal_aspect=True,
            color_by_time=True,
            mark_ends=True,
        ),
    ]


def test_renders_in_parallel_threads_match_serial_renders() -> None:
    serial = [job() for job in jobs()]
    with ThreadPoolExecutor(max_workers=4) as pool:
        parallel = [future.result() for future in [pool.submit(job) for job in jobs()]]
    assert parallel == serial


def test_summary_of_is_exported_for_structured_answers() -> None:
    assert summary_of(Line("v", "m/s", np.arange(3.0), np.array([1.0, 5.0, -2.0]))) == (3, -2.0, 5.0)


def test_dollar_signs_in_titles_labels_and_names_are_drawn_literally() -> None:
    """With mathtext on, ``$\\frac{$`` raised a ParseException (an internal error for the caller)."""
    broken = "$\\frac{$"
    odd = Line(f"{broken} topic", "$", T_S[:100], np.sin(T_S[:100]))
    png = render_timeseries([odd], style="line", title=broken)
    assert png.startswith(b"\x89PNG")
    assert render_histogram(np.sin(T_S), bins=None, label=broken, unit="$x^", title=broken).startswith(b"\x89PNG")
