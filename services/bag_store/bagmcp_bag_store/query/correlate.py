"""Correlation: the nearest message of another topic for each match, found by time index."""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from bagmcp_bag_store.results import Correlated
from bagmcp_shared.access import OpenBag
from bagmcp_shared.index import ColumnIndex
from bagmcp_shared.jsonify import fit

PARTNER_BUDGET_BYTES = 1500


def _times(ob: OpenBag, index: ColumnIndex | None, topic: str, lo: int, hi: int) -> npt.NDArray[np.int64]:
    if index is not None and index.columns(topic):
        return index.read(topic, [], start_ns=lo, stop_ns=hi).t_ns
    stamps = [raw.log_time_ns for raw in ob.reader.messages([topic], start_ns=lo, stop_ns=hi)]
    return np.asarray(stamps, dtype=np.int64)


def _nearest(candidates: npt.NDArray[np.int64], t: int, tolerance_ns: int) -> int | None:
    position = int(np.searchsorted(candidates, t))
    near = [int(candidates[i]) for i in (position - 1, position) if 0 <= i < len(candidates)]
    best = min(near, key=lambda c: abs(c - t), default=None)
    return best if best is not None and abs(best - t) <= tolerance_ns else None


def correlate(
    ob: OpenBag, index: ColumnIndex | None, topic: str, times_ns: list[int], *, tolerance_ns: int
) -> list[Correlated | None]:
    """For each time, the nearest message of ``topic`` within ``tolerance_ns`` (decoded), or None.

    Candidate times come from the index (or one raw pass); the chosen partners are then decoded in
    a single pass over their span.
    """
    name = ob.reader.topic_connections(topic)[0].topic
    if not times_ns:
        return []
    candidates = _times(ob, index, name, min(times_ns) - tolerance_ns, max(times_ns) + tolerance_ns + 1)
    chosen = [_nearest(candidates, t, tolerance_ns) for t in times_ns]
    wanted = {c for c in chosen if c is not None}
    decoded: dict[int, Correlated] = {}
    if wanted:
        for raw in ob.reader.messages([name], start_ns=min(wanted), stop_ns=max(wanted) + 1):
            if raw.log_time_ns in wanted and raw.log_time_ns not in decoded:
                data = fit(ob.reader.decode(raw), PARTNER_BUDGET_BYTES)
                decoded[raw.log_time_ns] = Correlated(
                    topic=name, time=ob.instant(raw.log_time_ns), delta_s=0.0, data=data
                )
    return [
        decoded[c].model_copy(update={"delta_s": (c - t) / 1e9}) if c is not None else None
        for c, t in zip(chosen, times_ns, strict=True)
    ]
