"""Time series of one TF edge (parent -> child): sampling with interpolation/clamping, rate, parent choice."""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from bagmcp_analysis.tf.quaternions import Quat, Vec3, normalize, slerp


@dataclass(frozen=True, eq=False)
class EdgeSeries:
    """All samples of one edge sorted by time; translations (n, 3) and rotations (n, 4) as x, y, z, w."""

    parent: str
    child: str
    static: bool
    t_ns: npt.NDArray[np.int64]
    translations: npt.NDArray[np.float64]
    rotations: npt.NDArray[np.float64]

    @property
    def count(self) -> int:
        return int(self.t_ns.shape[0])

    @property
    def first_ns(self) -> int:
        return int(self.t_ns[0])

    @property
    def last_ns(self) -> int:
        return int(self.t_ns[-1])


@dataclass(frozen=True)
class EdgeValue:
    """The edge transform T_parent_child at one time, and how it was obtained."""

    translation: Vec3
    rotation: Quat
    interpolated: bool
    extrapolated_s: float


def _sample(series: EdgeSeries, index: int) -> tuple[Vec3, Quat]:
    t = series.translations[index]
    r = series.rotations[index]
    return (float(t[0]), float(t[1]), float(t[2])), normalize((float(r[0]), float(r[1]), float(r[2]), float(r[3])))


def _exact(series: EdgeSeries, index: int, extrapolated_s: float) -> EdgeValue:
    translation, rotation = _sample(series, index)
    return EdgeValue(translation, rotation, interpolated=False, extrapolated_s=extrapolated_s)


def value_at(series: EdgeSeries, t_ns: int) -> EdgeValue:
    """T_parent_child at t_ns: static edges use the latest sample at or before t (else the first);
    dynamic edges interpolate (lerp + slerp) between the bracketing samples, clamping outside their range."""
    times = series.t_ns
    if series.static:
        index = max(0, int(np.searchsorted(times, t_ns, side="right")) - 1)
        return _exact(series, index, 0.0)
    if t_ns <= series.first_ns:
        return _exact(series, 0, (series.first_ns - t_ns) / 1e9)
    if t_ns >= series.last_ns:
        return _exact(series, series.count - 1, (t_ns - series.last_ns) / 1e9)
    index = int(np.searchsorted(times, t_ns, side="right")) - 1
    t0, t1 = int(times[index]), int(times[index + 1])
    if t0 == t_ns:
        return _exact(series, index, 0.0)
    fraction = (t_ns - t0) / (t1 - t0)
    (ax, ay, az), qa = _sample(series, index)
    (bx, by, bz), qb = _sample(series, index + 1)
    translation = (ax + fraction * (bx - ax), ay + fraction * (by - ay), az + fraction * (bz - az))
    return EdgeValue(translation, slerp(qa, qb, fraction), interpolated=True, extrapolated_s=0.0)


def rate_hz(series: EdgeSeries) -> float | None:
    """Mean publishing rate of a dynamic edge; None for static edges or fewer than two distinct times."""
    if series.static or series.count < 2 or series.last_ns <= series.first_ns:
        return None
    return (series.count - 1) / ((series.last_ns - series.first_ns) / 1e9)


def nearest_ns(series: EdgeSeries, t_ns: int) -> int:
    """Stamp of the sample nearest to t_ns (the earlier one on a tie)."""
    index = int(np.searchsorted(series.t_ns, t_ns, side="left"))
    if index <= 0:
        return series.first_ns
    if index >= series.count:
        return series.last_ns
    before, after = int(series.t_ns[index - 1]), int(series.t_ns[index])
    return before if t_ns - before <= after - t_ns else after


def _published_key(series: EdgeSeries, t_ns: int | None) -> tuple[int, int, str]:
    """Sort key: edges published at or before t rank by their latest stamp, unpublished ones by earliest first."""
    if t_ns is None:
        return (1, series.last_ns, series.parent)
    index = int(np.searchsorted(series.t_ns, t_ns, side="right")) - 1
    if index >= 0:
        return (1, int(series.t_ns[index]), series.parent)
    return (0, -series.first_ns, series.parent)


def parents_at(edges: Iterable[EdgeSeries], t_ns: int | None) -> dict[str, str]:
    """Parent of every child frame at t_ns; a child with several parents takes the most recently published one
    (at t_ns, or overall when t_ns is None)."""
    best: dict[str, EdgeSeries] = {}
    for series in edges:
        current = best.get(series.child)
        if current is None or _published_key(series, t_ns) > _published_key(current, t_ns):
            best[series.child] = series
    return {child: series.parent for child, series in best.items()}
