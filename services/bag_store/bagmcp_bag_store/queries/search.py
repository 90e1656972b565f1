"""search_messages: a typed condition over a topic, answered from the columnar index when it can.

The tool's arguments are parsed once per call into a ``PreparedSearch`` (the bag's spelling of the topic,
log level names as numbers, the typed condition of query/conditions.py) on one opening of the bag, which
the "is it small" estimate and the search itself share when the search runs inline: each ``access.open``
is a catalog read (Redis) and a lease on the opened-bag cache, and a regex is compiled once.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from bagmcp_bag_store.queries.conditions import SearchCondition, parse_condition
from bagmcp_bag_store.queries.correlate import correlate
from bagmcp_bag_store.queries.search_logs import log_details, with_level_numbers
from bagmcp_bag_store.queries.search_params import SearchParams
from bagmcp_bag_store.queries.search_scan import BagScan, Found
from bagmcp_bag_store.reports import ClosestApproach, SearchMatch, SearchResult
from bagmcp_shared.access import BagAccess, OpenBag
from bagmcp_shared.jobs import Progress, Unreported


@dataclass(frozen=True)
class PreparedSearch:
    """A request checked against its open bag: topic as the bag spells it, level names as numbers, the
    condition typed and the window in epoch ns."""

    ob: OpenBag
    req: SearchParams
    condition: SearchCondition
    lo: int
    hi: int

    @classmethod
    def of(cls, ob: OpenBag, req: SearchParams) -> PreparedSearch:
        req = with_level_numbers(ob, req.model_copy(update={"topic": ob.topic_name(req.topic)}))
        condition = parse_condition(req.condition, req.value, req.field)
        lo, hi = ob.window(req.start, req.end)
        return cls(ob, req, condition, lo, hi)

    @property
    def small(self) -> bool:
        """Quick enough to answer while the caller waits: from the index, or over few messages."""
        topic = self.req.topic
        from_index = self.condition.columnar and self.ob.indexed(topic) and not self.req.correlate_topic
        return from_index or self.ob.short(topic)


def _closest(ob: OpenBag, found: Found) -> ClosestApproach | None:
    if found.distance is None or found.xy is None or not len(found.distance):
        return None
    best = int(np.argmin(found.distance))
    return ClosestApproach(
        distance_m=float(found.distance[best]),
        x=float(found.xy[0][best]),
        y=float(found.xy[1][best]),
        time=ob.instant(int(found.t_ns[best])),
    )


def _within(matches: list[SearchMatch], budget: int) -> list[SearchMatch]:
    """The leading matches whose JSON fits the byte budget (at least one)."""
    kept: list[SearchMatch] = []
    used = 0
    for match in matches:
        used += len(match.model_dump_json())
        if kept and used > budget:
            break
        kept.append(match)
    return kept


def _run(search: PreparedSearch, progress: Progress, *, budget_bytes: int, use_index: bool) -> SearchResult:
    ob, req = search.ob, search.req
    index = ob.index if use_index else None
    found = search.condition.find(BagScan(ob, req.topic, req.field, index, search.lo, search.hi, progress))
    hit_times = found.t_ns[found.mask]
    shown = [int(t) for t in hit_times[: req.limit]]
    partners = (
        correlate(ob, index, req.correlate_topic, shown, tolerance_ns=int(req.correlate_tolerance_s * 1e9))
        if req.correlate_topic
        else [None] * len(shown)
    )
    distances = found.distance[found.mask] if found.distance is not None else None
    details = log_details(ob, req.topic, shown)
    matches = [
        SearchMatch(
            time=ob.instant(t),
            value=found.values[i],
            details=details[i],
            correlated=partners[i],
            distance_m=float(distances[i]) if distances is not None else None,
        )
        for i, t in enumerate(shown)
    ]
    matches = _within(matches, budget_bytes)
    progress(1.0, "done")
    return SearchResult(
        bag=ob.name,
        topic=req.topic,
        condition=req.condition,
        field=found.field,
        start=ob.instant(search.lo),
        end=ob.instant(search.hi),
        clock="log_time",
        scanned=len(found.t_ns),
        total=int(found.mask.sum()),
        returned=len(matches),
        truncated=len(hit_times) > len(matches),
        matches=matches,
        closest=_closest(ob, found),
        source="index" if found.source == "index" else "bag",
    )


def search_messages(
    access: BagAccess, req: SearchParams, progress: Progress, *, budget_bytes: int, use_index: bool = True
) -> SearchResult:
    with access.open(req.bag) as ob:
        return _run(PreparedSearch.of(ob, req), progress, budget_bytes=budget_bytes, use_index=use_index)


def search_if_small(access: BagAccess, req: SearchParams, *, budget_bytes: int) -> SearchResult | None:
    """The search done now when it is small, else None (for a job): the estimate and the search share one
    opening of the bag and one parse of the request."""
    with access.open(req.bag) as ob:
        search = PreparedSearch.of(ob, req)
        return _run(search, Unreported(), budget_bytes=budget_bytes, use_index=True) if search.small else None
