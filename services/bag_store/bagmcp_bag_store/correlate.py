"""Correlation: the nearest message of another topic for each match, found by time index."""

from __future__ import annotations

import numpy as np

from bagmcp_bag_store.opened import OpenBag
from bagmcp_bag_store.results import Correlated
from bagmcp_shared.columns import ColumnIndex
from bagmcp_shared.jsonify import to_json


def _times(ob: OpenBag, index: ColumnIndex | None, topic: str, lo: int, hi: int) -> np.ndarray:
    if index is not None and index.columns(topic):
        return index.read(topic, [], start_ns=lo, stop_ns=hi).t_ns
    stamps = [raw.log_time_ns for raw in ob.reader.messages([topic], start_ns=lo, stop_ns=hi)]
    return np.asarray(stamps, dtype=np.int64)


def correlate(
    ob: OpenBag, index: ColumnIndex | None, topic: str, times_ns: list[int], *, tolerance_ns: int
) -> list[Correlated | None]:
    """For each time, the nearest message of ``topic`` within ``tolerance_ns`` (decoded), or None."""
    name = ob.reader.topic_connections(topic)[0].topic
    if not times_ns:
        return []
    candidates = _times(ob, index, name, min(times_ns) - tolerance_ns, max(times_ns) + tolerance_ns + 1)
    found: list[Correlated | None] = []
    for t in times_ns:
        position = int(np.searchsorted(candidates, t))
        near = [int(candidates[i]) for i in (position - 1, position) if 0 <= i < len(candidates)]
        best = min(near, key=lambda c: abs(c - t), default=None)
        if best is None or abs(best - t) > tolerance_ns:
            found.append(None)
            continue
        raw = next(ob.reader.messages([name], start_ns=best, stop_ns=best + 1))
        found.append(
            Correlated(
                topic=name,
                time=ob.instant(best),
                delta_s=(best - t) / 1e9,
                data=to_json(ob.reader.decode(raw), max_items=16),
            )
        )
    return found
