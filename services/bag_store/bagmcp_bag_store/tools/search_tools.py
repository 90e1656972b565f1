"""The declarations of the long-work tools on one bag: search_messages and filter_bag (inline when small,
else a job); their params models live beside their work (query/search_params.py, filtering.py)."""

from __future__ import annotations

from bagmcp_bag_store.filtering import FilterParams, filter_bag
from bagmcp_bag_store.queries.search import search_if_small, search_messages
from bagmcp_bag_store.queries.search_params import SearchParams
from bagmcp_bag_store.reports import FilterResult, SearchResult
from bagmcp_bag_store.tools.store import Store
from bagmcp_kit.arguments import WRITES
from bagmcp_kit.declared import Declared
from bagmcp_shared.jobs import Progress


def _search_summary(result: SearchResult) -> str:
    closest = f"; closest approach {result.closest.distance_m:.3f} m" if result.closest else ""
    if result.condition in ("max", "min") and result.matches:
        peak = result.matches[0]
        value = f"{peak.value:.6g}" if isinstance(peak.value, float) else str(peak.value)
        return (
            f"{result.condition} {result.field} = {value} first at {peak.time.offset_s:.3f} s; "
            f"{result.total} of {result.scanned} messages have it"
        )
    return f"{result.total} of {result.scanned} messages match{closest}"


def _filter_summary(result: FilterResult) -> str:
    existed = "" if result.created else " (it existed already)"
    note = f"; {result.note}" if result.note else ""
    return f"bag {result.name} ({result.bag_id}) with {result.message_count} messages{existed}{note}"


def _search(store: Store, params: SearchParams, progress: Progress) -> SearchResult:
    return search_messages(store.access, params, progress, budget_bytes=store.budget_bytes)


def _filter(store: Store, params: FilterParams, progress: Progress) -> FilterResult:
    return filter_bag(store.access, store.shelf, store.ingestor, params, progress)


SEARCH = Declared(
    "search_messages",
    "Messages meeting a condition: count, first matches (max/min: where a field peaks), closest approach for "
    'near_position. Example: topic=/odom, condition=near_position, value={"x":1,"y":-2,"radius":0.5}.',
    SearchParams,
    SearchResult,
    _search,
    _search_summary,
    inline=lambda store, p: search_if_small(store.access, p, budget_bytes=store.budget_bytes),
    job="search",
)
FILTER = Declared(
    "filter_bag",
    "A new bag from some topics, a time window and/or rate limits, stored under `name` (the same request gives "
    'the same bag; needs the upload scope). Example: include_topics=["/cmd_vel", "/odom"].',
    FilterParams,
    FilterResult,
    _filter,
    _filter_summary,
    annotations=WRITES,
    job="filter",
)
