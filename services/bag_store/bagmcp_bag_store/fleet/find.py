"""find_bags: bags meeting every typed condition given, with the evidence for each (when, how much).

Each condition is one fixed SQL query over a view (the caller's values bound as parameters, never pasted
into the text), run by the same engine and limits as query_bags; a bag matches when it answers all of them.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

from pydantic import BaseModel, Field

from bagmcp_bag_store.errors import QueryError
from bagmcp_bag_store.fleet.engine import FleetEngine, Progress
from bagmcp_bag_store.fleet.find_params import FindParams
from bagmcp_shared.errors import ArgumentError
from bagmcp_shared.log_levels import level_rank
from bagmcp_shared.timebase import EPOCH_THRESHOLD_S, iso_from_ns, parse_time

Row = dict[str, object]


class Evidence(BaseModel):
    condition: str
    detail: str
    offset_s: float | None = Field(default=None, description="when, s from the bag's start")
    value: float | None = Field(default=None, description="how much (m/s, m, s, count)")


class Match(BaseModel):
    bag: str
    evidence: list[Evidence]


class FindAnswer(BaseModel):
    matches: list[Match]
    total: int = Field(description="bags matching every condition")
    truncated: bool
    bags_queried: int
    missing_bags: list[str] = Field(default_factory=list, description="bags whose rows are not stored yet")


@dataclass(frozen=True)
class Probe:
    condition: str
    sql: str
    params: tuple[object, ...]
    evidence: Callable[[Row], Evidence]


def _f(row: Row, key: str) -> float | None:
    value = row.get(key)
    return float(value) if isinstance(value, int | float) else None


def _at(row: Row) -> str:
    offset = _f(row, "offset_s")
    return f" at {offset:.2f} s" if offset is not None else ""


def _message_type(text: str) -> str:
    parts = text.strip().split("/")
    return f"{parts[0]}/msg/{parts[1]}" if len(parts) == 2 else text.strip()


def _epoch_s(value: float | str, what: str) -> float:
    stamp_ns = parse_time(value, start_ns=0)
    if isinstance(value, int | float) and abs(value) < EPOCH_THRESHOLD_S:
        raise ArgumentError(f"{what} must be an ISO-8601 time or epoch seconds, not {value!r}")
    return stamp_ns / 1e9


_TOPIC_IS = "lower(trim(topic, '/')) = lower(trim($1, '/'))"
_PER_TOPIC = "SELECT bag, string_agg(topic || ' (' || type || ')', ', ') AS topics, sum(count)::BIGINT AS n FROM topics"
_SPEED = (
    "SELECT bag, max(speed) AS v, arg_max(offset_s, speed) AS offset_s, arg_max(topic, speed) AS topic, "
    "arg_max(x, speed) AS x, arg_max(y, speed) AS y FROM poses WHERE speed > $1 GROUP BY bag"
)
_SCAN = (
    "SELECT bag, min(offset_s) AS offset_s, count(*) AS n, min(min_range) AS v, "
    "arg_min(topic, offset_s) AS topic FROM scans WHERE min_range < $1 GROUP BY bag"
)
_GAP = (
    "SELECT bag, max(max_gap_s) AS v, arg_max(topic, max_gap_s) AS topic, arg_max(max_gap_at_s, max_gap_s) "
    "AS offset_s FROM topics WHERE max_gap_s > $1 AND ($2 IS NULL OR lower(trim(topic, '/')) = lower(trim($2, '/'))) "
    "GROUP BY bag"
)


def _topics(condition: str) -> Callable[[Row], Evidence]:
    return lambda r: Evidence(condition=condition, detail=f"{r['topics']}: {r['n']} messages", value=_f(r, "n"))


def _measured(condition: str, detail: Callable[[Row], str]) -> Callable[[Row], Evidence]:
    return lambda r: Evidence(condition=condition, value=_f(r, "v"), offset_s=_f(r, "offset_s"), detail=detail(r))


def _speed(r: Row) -> str:
    return f"max speed {r['v']:.3f} m/s{_at(r)} on {r['topic']} at ({r['x']:.2f}, {r['y']:.2f})"


def _probes(p: FindParams) -> list[Probe]:
    """One probe per condition given, in the order of the tool's arguments."""
    probes: list[Probe] = []
    if p.topic:
        probes.append(Probe("topic", f"{_PER_TOPIC} WHERE {_TOPIC_IS} GROUP BY bag", (p.topic,), _topics("topic")))
    if p.type:
        sql = f"{_PER_TOPIC} WHERE type = $1 OR type LIKE '%/' || $1 GROUP BY bag"
        probes.append(Probe("type", sql, (_message_type(p.type),), _topics("type")))
    if p.between is not None:
        low, high = (_epoch_s(value, "between") for value in p.between)
        sql = "SELECT bag, start, duration_s FROM bags WHERE start >= $1 AND start <= $2"
        probes.append(Probe("recorded", sql, (low, high), _recorded))
    if p.log_level or p.log_node or p.log_text:
        probes.append(_log_probe(p))
    if p.speed_above is not None:
        probes.append(Probe("speed_above", _SPEED, (p.speed_above,), _measured("speed_above", _speed)))
    if p.near is not None:
        probes.append(_near_probe(*p.near))
    if p.scan_below is not None:
        below = p.scan_below
        detail = _measured(
            "scan_below",
            lambda r: f"{r['topic']} first below {below} m{_at(r)}; {r['n']} scans below, closest {r['v']:.3f} m",
        )
        probes.append(Probe("scan_below", _SCAN, (below,), detail))
    if p.gap_above is not None:
        detail = _measured("gap_above", lambda r: f"{r['topic']} silent for {r['v']:.3f} s{_at(r)}")
        probes.append(Probe("gap_above", _GAP, (p.gap_above, p.topic), detail))
    if not probes:
        raise ArgumentError("give at least one condition (e.g. log_level='ERROR', speed_above=1, topic='/scan')")
    return probes


def _recorded(row: Row) -> Evidence:
    start = _f(row, "start") or 0.0
    detail = f"recorded from {iso_from_ns(round(start * 1e9))} for {_f(row, 'duration_s') or 0.0:.1f} s"
    return Evidence(condition="recorded", detail=detail, value=_f(row, "duration_s"))


def _log_probe(p: FindParams) -> Probe:
    rank = level_rank(p.log_level) if p.log_level else 0
    sql = (
        "SELECT bag, count(*) AS n, arg_min(offset_s, t) AS offset_s, arg_min(level, t) AS level, "
        "arg_min(node, t) AS node, arg_min(text, t) AS text FROM logs WHERE level_rank >= $1 "
        "AND ($2 IS NULL OR contains(lower(node), lower($2))) AND ($3 IS NULL OR contains(lower(text), lower($3))) "
        "GROUP BY bag"
    )

    def evidence(r: Row) -> Evidence:
        first = f"first{_at(r)}: [{r['level']}] {r['node']}: {str(r['text'])[:200]}"
        return Evidence(
            condition="log", value=_f(r, "n"), offset_s=_f(r, "offset_s"), detail=f"{r['n']} records; {first}"
        )

    return Probe("log", sql, (rank, p.log_node, p.log_text), evidence)


def _near_probe(x: float, y: float, radius_m: float) -> Probe:
    sql = (
        "SELECT bag, min(d) AS v, arg_min(offset_s, d) AS offset_s, arg_min(x, d) AS x, arg_min(y, d) AS y, "
        "arg_min(topic, d) AS topic, min(offset_s) AS first_s FROM "
        "(SELECT *, sqrt((x - $1) * (x - $1) + (y - $2) * (y - $2)) AS d FROM poses) WHERE d <= $3 GROUP BY bag"
    )

    def evidence(r: Row) -> Evidence:
        detail = (
            f"closest {r['v']:.3f} m{_at(r)} at ({r['x']:.2f}, {r['y']:.2f}) on {r['topic']}; "
            f"first within {radius_m} m at {r['first_s']:.2f} s"
        )
        return Evidence(condition="near", value=_f(r, "v"), offset_s=_f(r, "offset_s"), detail=detail)

    return Probe("near", sql, (x, y, radius_m), evidence)


def find_bags(
    engine: FleetEngine, p: FindParams, readable: Sequence[str], progress: Progress | None = None
) -> FindAnswer:
    """Bags meeting every condition of ``p`` (names in order), at most ``p.limit`` of them, with evidence."""
    probes = _probes(p)
    found: dict[str, list[Evidence]] | None = None
    bags, missing = 0, set[str]()
    for number, probe in enumerate(probes):
        outcome = engine.run(probe.sql, readable=readable, max_rows=1_000_000, params=probe.params, progress=progress)
        bags, missing = outcome.bags, missing | set(outcome.missing)
        rows = {str(r["bag"]): probe.evidence(r) for r in outcome.table.to_pylist()}
        found = (
            {b: [*e, rows[b]] for b, e in found.items() if b in rows}
            if found is not None
            else {b: [e] for b, e in rows.items()}
        )
        if progress is not None:
            progress((number + 1) / len(probes), f"checked {probe.condition}")
    if found is None:
        raise QueryError("no condition was checked")
    names = sorted(found)
    matches = [Match(bag=b, evidence=found[b]) for b in names[: p.limit]]
    return FindAnswer(
        matches=matches,
        total=len(names),
        truncated=len(names) > p.limit,
        bags_queried=bags,
        missing_bags=sorted(missing),
    )
