"""Laser scan plots (render_scan): polar view with forward up and left on the left (REP 103).

Theta zero points up (North), angles grow counter-clockwise; only finite ranges in (0, range_max_m]
are drawn; with within_m a dashed circle marks that distance and the points inside it are red; an orange
diamond marks the closest return, with its range and bearing in the legend.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt
from matplotlib.projections.polar import PolarAxes
from matplotlib.ticker import FuncFormatter

from bagmcp_plotting.drawing.canvas import LEGEND_SIZE, PALETTE, TICK_SIZE, new_figure, to_png
from bagmcp_plotting.drawing.decimate import extreme_indices

MAX_POINTS = 20_000
INSIDE_COLOR = "#d62728"
CLOSEST_COLOR = "#ff7f0e"
ANGLE_TICKS_DEG = (0, 45, 90, 135, 180, 225, 270, 315)
ANGLE_LABELS = ("0° front", "45°", "90° left", "135°", "180° back", "-135°", "-90° right", "-45°")


@dataclass(frozen=True)
class ScanPoints:
    """What a scan plot draws: the valid returns (thinned, extremes kept), how many lie inside the within
    circle (counted before thinning) and the closest return (bearing in degrees, + = left)."""

    theta_rad: npt.NDArray[np.float64]
    range_m: npt.NDArray[np.float64]
    inside_count: int
    closest: tuple[float, float] | None  # (range m, bearing deg)


def scan_points(
    angles_rad: npt.NDArray[np.float64],
    ranges_m: npt.NDArray[np.float64],
    *,
    range_max_m: float,
    within_m: float | None,
) -> ScanPoints:
    angles = np.asarray(angles_rad, dtype=np.float64)
    ranges = np.asarray(ranges_m, dtype=np.float64)
    if angles.shape != ranges.shape or angles.ndim != 1:
        raise ValueError(f"angles and ranges must be 1-D of the same length, not {angles.shape} and {ranges.shape}.")
    if not np.isfinite(range_max_m) or range_max_m <= 0:
        raise ValueError(f"range_max_m must be a positive number of metres, not {range_max_m}.")
    if within_m is not None and not (np.isfinite(within_m) and within_m > 0):
        raise ValueError(f"within_m must be a positive number of metres, not {within_m}.")
    valid = np.isfinite(angles) & np.isfinite(ranges) & (ranges > 0) & (ranges <= range_max_m)
    theta, radius = angles[valid], ranges[valid]
    closest = None
    if radius.size:
        best = int(np.argmin(radius))
        closest = (float(radius[best]), float(np.degrees(np.angle(np.exp(1j * theta[best])))))
    shown = extreme_indices(radius, max_points=MAX_POINTS)  # the closest return is always drawn
    inside = int((radius <= within_m).sum()) if within_m is not None else 0
    return ScanPoints(theta_rad=theta[shown], range_m=radius[shown], inside_count=inside, closest=closest)


def render_scan(
    *,
    angles_rad: npt.NDArray[np.float64],
    ranges_m: npt.NDArray[np.float64],
    title: str,
    range_max_m: float,
    within_m: float | None = None,
) -> bytes:
    """PNG polar plot of one scan, robot at the centre, radial axis in metres."""
    points = scan_points(angles_rad, ranges_m, range_max_m=range_max_m, within_m=within_m)
    theta, radius = points.theta_rad, points.range_m
    figure = new_figure(title=title)
    axes = figure.add_subplot(projection="polar")
    if not isinstance(axes, PolarAxes):
        raise TypeError("matplotlib did not create polar axes.")
    _orient(axes)
    inside = radius <= within_m if within_m is not None else np.zeros(radius.shape, dtype=bool)
    axes.scatter(theta[~inside], radius[~inside], s=8, color=PALETTE[0], linewidths=0, label="scan points")
    if within_m is not None:
        circle = np.linspace(0.0, 2.0 * np.pi, 361)
        axes.plot(
            circle, np.full(circle.shape, within_m), "--", color="black", linewidth=1.2, label=f"within {within_m:g} m"
        )
        axes.scatter(
            theta[inside],
            radius[inside],
            s=10,
            color=INSIDE_COLOR,
            linewidths=0,
            label=f"inside {within_m:g} m ({points.inside_count})",
        )
    if points.closest is not None:
        _mark_closest(axes, *points.closest)
    axes.plot([0.0], [0.0], marker="^", color="black", markersize=12, linestyle="none", label="robot (forward up)")
    axes.set_rlim(0.0, _radial_limit_m(radius, range_max_m=range_max_m, within_m=within_m))
    figure.legend(loc="upper right", fontsize=LEGEND_SIZE)  # over the empty corner: the plot never moves
    return to_png(figure)


def _mark_closest(axes: PolarAxes, range_m: float, bearing_deg: float) -> None:
    """A diamond on the closest return, its range and bearing in the legend."""
    axes.plot(
        [np.radians(bearing_deg)],
        [range_m],
        marker="D",
        markersize=9,
        color=CLOSEST_COLOR,
        markeredgecolor="black",
        linestyle="none",
        label=f"closest {range_m:.2f} m at {bearing_deg:.0f}°",
    )


def _orient(axes: PolarAxes) -> None:
    axes.set_theta_zero_location("N")
    axes.set_theta_direction(1)
    axes.set_thetagrids(ANGLE_TICKS_DEG, ANGLE_LABELS, fontsize=TICK_SIZE)
    axes.yaxis.set_major_formatter(FuncFormatter(lambda value, _: f"{value:g} m"))
    axes.tick_params(labelsize=TICK_SIZE)
    axes.grid(visible=True, alpha=0.35)


def _radial_limit_m(radius: npt.NDArray[np.float64], *, range_max_m: float, within_m: float | None) -> float:
    """10 % beyond the farthest point or the within circle; range_max_m when there is neither."""
    farthest = max(float(radius.max()) if radius.size else 0.0, within_m or 0.0)
    return 1.1 * farthest if farthest > 0 else range_max_m
