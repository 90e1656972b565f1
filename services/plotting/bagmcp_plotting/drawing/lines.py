"""The Line series type shared by the time-series and overlay renderers, and its summary.

summary_of gives the (count, min, max) of a line's finite points; plot_points gives the finite,
min/max-decimated points that are actually drawn, broken where the series has gaps.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from bagmcp_plotting.drawing.decimate import minmax_decimate

DECIMATE_COLUMNS = 1500
SCATTER_SAMPLE_POINTS = 3000
GAP_PERIODS = 5.0  # a line breaks where no point came for this many median periods


@dataclass(frozen=True, eq=False)
class Line:
    """One named series: y against x (same length, 1-D), y in `unit` when known."""

    label: str
    unit: str | None
    x: npt.NDArray[np.float64]
    y: npt.NDArray[np.float64]

    def __post_init__(self) -> None:
        if np.shape(self.x) != np.shape(self.y) or np.ndim(self.x) != 1:
            raise ValueError(
                f"The series {self.label!r} needs 1-D x and y of the same length, "
                f"not shapes {np.shape(self.x)} and {np.shape(self.y)}."
            )


def finite_points(line: Line) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """The points whose x and y are both finite."""
    x = np.asarray(line.x, dtype=np.float64)
    y = np.asarray(line.y, dtype=np.float64)
    keep = np.isfinite(x) & np.isfinite(y)
    return x[keep], y[keep]


def plot_points(line: Line) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """Finite points, min/max decimated to what a 1000-pixel-wide plot can show, with a NaN (a break in
    the line) wherever the series has a gap, so a line never bridges missing data."""
    x, y = finite_points(line)
    drawn_x, drawn_y = minmax_decimate(x, y, columns=DECIMATE_COLUMNS)
    if x.size < 3:
        return drawn_x, drawn_y
    column_s = float(x.max() - x.min()) / DECIMATE_COLUMNS
    limit = max(GAP_PERIODS * float(np.median(np.abs(np.diff(x)))), 2 * column_s)
    breaks = np.flatnonzero(np.diff(drawn_x) > limit) + 1
    return np.insert(drawn_x, breaks, np.nan), np.insert(drawn_y, breaks, np.nan)


def scatter_points(line: Line) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """Min/max points plus an evenly strided sample, so a scatter shows the spread and not just the envelope."""
    x, y = finite_points(line)
    low_x, low_y = minmax_decimate(x, y, columns=DECIMATE_COLUMNS)
    if low_x.size == x.size:
        return x, y
    stride = -(-x.size // SCATTER_SAMPLE_POINTS)
    return np.concatenate([low_x, x[::stride]]), np.concatenate([low_y, y[::stride]])


def summary_of(line: Line) -> tuple[int, float | None, float | None]:
    """(number of finite points, min y, max y); min and max are None when there is no finite point."""
    _, y = finite_points(line)
    if y.size == 0:
        return 0, None, None
    return int(y.size), float(y.min()), float(y.max())


def magnitude_of(line: Line) -> float | None:
    """Largest |y| over the finite points; None when there is none or it is zero."""
    _, y = finite_points(line)
    if y.size == 0:
        return None
    peak = float(np.abs(y).max())
    return peak if peak > 0 else None
