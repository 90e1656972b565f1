"""Decimation of long series so plots stay small but keep every spike and the whole extent.

minmax_decimate splits the x range into equal-width columns and keeps, per column, the points with the
smallest and the largest y, so the drawn envelope matches the full series. extreme_indices thins paths
and scans (points in order, several coordinates) keeping each run's extremes of every coordinate.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt


def minmax_decimate(
    x: npt.NDArray[np.float64], y: npt.NDArray[np.float64], *, columns: int = 1500
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """At most 2*columns points (in x order) keeping each column's min and max y; short series unchanged."""
    if columns < 1:
        raise ValueError(f"columns must be at least 1, not {columns}.")
    x = np.asarray(x, dtype=np.float64)
    y = np.asarray(y, dtype=np.float64)
    if x.shape != y.shape or x.ndim != 1:
        raise ValueError(f"x and y must be 1-D arrays of the same length, not shapes {x.shape} and {y.shape}.")
    if x.size <= 2 * columns:
        return x, y
    keep = np.isfinite(x) & np.isfinite(y)
    x, y = x[keep], y[keep]
    if x.size <= 2 * columns:
        return x, y
    if np.any(np.diff(x) < 0):
        order = np.argsort(x, kind="stable")
        x, y = x[order], y[order]
    column = _column_of(x, columns=columns)
    starts = np.flatnonzero(np.r_[True, column[1:] != column[:-1]])
    counts = np.diff(np.r_[starts, x.size])
    lowest = _first_per_column(y == np.repeat(np.minimum.reduceat(y, starts), counts), column)
    highest = _first_per_column(y == np.repeat(np.maximum.reduceat(y, starts), counts), column)
    chosen = np.union1d(lowest, highest)
    return x[chosen], y[chosen]


def _column_of(x: npt.NDArray[np.float64], *, columns: int) -> npt.NDArray[np.intp]:
    """Column index of each sorted x value for `columns` equal-width bins over [x[0], x[-1]]."""
    span = x[-1] - x[0]
    if span <= 0:
        return np.zeros(x.size, dtype=np.intp)
    column = np.floor((x - x[0]) / span * columns).astype(np.intp)
    clipped: npt.NDArray[np.intp] = np.minimum(column, columns - 1)
    return clipped


def _first_per_column(hit: npt.NDArray[np.bool_], column: npt.NDArray[np.intp]) -> npt.NDArray[np.intp]:
    """Index of the first hit in each column (columns are contiguous because x is sorted)."""
    where = np.flatnonzero(hit)
    hit_column = column[where]
    return where[np.r_[True, hit_column[1:] != hit_column[:-1]]]


def extreme_indices(*values: npt.NDArray[np.float64], max_points: int) -> npt.NDArray[np.intp]:
    """Indices, in order, of at most about ``max_points`` of the points whose coordinates are ``values``.

    The points are cut into runs of consecutive points; each run keeps its first point and the points with
    the smallest and largest value of every array, so the extent (every minimum and maximum) survives and
    the path keeps its shape. All indices when there are no more than ``max_points``."""
    count = int(values[0].size) if values else 0
    if max_points < 1:
        raise ValueError(f"max_points must be at least 1, not {max_points}.")
    if any(v.shape != (count,) for v in values):
        raise ValueError("every coordinate array must be 1-D with one value per point.")
    if count <= max_points:
        return np.arange(count, dtype=np.intp)
    runs = max(1, max_points // (1 + 2 * len(values)))
    size = -(-count // runs)
    starts = np.arange(0, count, size, dtype=np.intp)
    kept = [starts, np.array([count - 1], dtype=np.intp)]
    for array in values:
        for fill, pick in ((np.inf, np.argmin), (-np.inf, np.argmax)):
            padded = np.full(starts.size * size, fill, dtype=np.float64)
            padded[:count] = array
            kept.append(starts + pick(padded.reshape(starts.size, size), axis=1).astype(np.intp))
    indices: npt.NDArray[np.intp] = np.unique(np.concatenate(kept))
    return indices
