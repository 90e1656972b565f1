"""ROS log records: conversion from decoded Log messages, filtering and summaries (counts, errors, bursts).

Level names and parsing live in log_levels and are re-exported here.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from bagmcp_shared.log_levels import LEVEL_NAMES, level_name, level_rank, parse_level

__all__ = [
    "LEVEL_NAMES",
    "Burst",
    "LogRecord",
    "LogSummary",
    "filter_records",
    "level_name",
    "parse_level",
    "record_from_message",
    "summarize_records",
]


@dataclass(frozen=True)
class LogRecord:
    """One log message; level is one of LEVEL_NAMES, level_raw the value in the message."""

    t_ns: int
    level: str
    level_raw: int
    node: str
    text: str
    file: str
    function: str
    line: int


@dataclass(frozen=True)
class Burst:
    """A maximal stretch of overlapping windows of burst_window_s, each holding at least burst_min records."""

    start_ns: int
    end_ns: int
    count: int
    top_node: str
    worst_level: str


@dataclass(frozen=True)
class LogSummary:
    """Counts per level (all five names) and per node (most frequent first), key records and bursts."""

    total: int
    by_level: dict[str, int]
    by_node: dict[str, int]
    first_error: LogRecord | None
    last_error: LogRecord | None
    first_warning: LogRecord | None
    bursts: list[Burst]


def record_from_message(message: object, t_ns: int, *, ros2: bool) -> LogRecord:
    """Read level, name, msg, file, function and line from a decoded rosgraph_msgs/Log or rcl_interfaces Log."""
    raw_level = getattr(message, "level", None)
    if raw_level is None:
        raise ValueError("The message has no 'level' field; pick a rosgraph_msgs/Log or rcl_interfaces/msg/Log topic.")
    level_raw = int(raw_level)
    return LogRecord(
        t_ns=int(t_ns),
        level=level_name(level_raw, ros2=ros2),
        level_raw=level_raw,
        node=str(getattr(message, "name", "")),
        text=str(getattr(message, "msg", "")),
        file=str(getattr(message, "file", "")),
        function=str(getattr(message, "function", "")),
        line=int(getattr(message, "line", 0)),
    )


def filter_records(
    records: Sequence[LogRecord],
    *,
    level: str | int | None = None,
    min_level: str | int | None = None,
    node: str | None = None,
    contains: str | None = None,
    start_ns: int | None = None,
    end_ns: int | None = None,
) -> list[LogRecord]:
    """Records matching every given condition, in input order.

    level: exactly this level; min_level: this level or more severe (names, aliases or numbers).
    node: exact node name ignoring a leading '/'; when no record has that exact name, every node whose name
    contains it (case-insensitive) matches instead. contains: case-insensitive substring of the text.
    start_ns/end_ns: inclusive time window.
    """
    exact = None if level is None else parse_level(level, ros2=True)
    floor = None if min_level is None else level_rank(parse_level(min_level, ros2=True))
    wanted = None if node is None else node.lstrip("/")
    exact_node = wanted is not None and any(record.node.lstrip("/") == wanted for record in records)
    needle = None if contains is None else contains.casefold()
    return [
        record
        for record in records
        if (exact is None or record.level == exact)
        and (floor is None or level_rank(record.level) >= floor)
        and (wanted is None or _node_matches(record.node, wanted, exact=exact_node))
        and (needle is None or needle in record.text.casefold())
        and (start_ns is None or record.t_ns >= start_ns)
        and (end_ns is None or record.t_ns <= end_ns)
    ]


def _node_matches(node: str, wanted: str, *, exact: bool) -> bool:
    name = node.lstrip("/")
    return name == wanted if exact else wanted.casefold() in name.casefold()


def summarize_records(
    records: Sequence[LogRecord], *, burst_window_s: float = 1.0, burst_min: int = 10, max_items: int = 10
) -> LogSummary:
    """Counts per level and node, first/last error (ERROR or FATAL), first warning (WARN or worse), bursts."""
    if not burst_window_s > 0 or burst_min < 2 or max_items < 1:
        raise ValueError("burst_window_s must be positive, burst_min at least 2 and max_items at least 1.")
    ordered = sorted(records, key=lambda record: record.t_ns)
    levels = Counter(record.level for record in ordered)
    nodes = Counter(record.node for record in ordered)
    top_nodes = sorted(nodes.items(), key=lambda item: (-item[1], item[0]))[:max_items]
    errors = [record for record in ordered if level_rank(record.level) >= level_rank("ERROR")]
    warnings = (record for record in ordered if level_rank(record.level) >= level_rank("WARN"))
    return LogSummary(
        total=len(ordered),
        by_level={name: levels.get(name, 0) for name in LEVEL_NAMES},
        by_node=dict(top_nodes),
        first_error=errors[0] if errors else None,
        last_error=errors[-1] if errors else None,
        first_warning=next(warnings, None),
        bursts=_bursts(ordered, round(burst_window_s * 1e9), burst_min)[:max_items],
    )


def _bursts(ordered: list[LogRecord], window_ns: int, burst_min: int) -> list[Burst]:
    """Maximal runs covered by windows [t_i, t_i + window] holding >= burst_min records.

    Most intense first: the largest number of records in one window, then the total count.
    """
    stamps = np.array([record.t_ns for record in ordered], dtype=np.int64)
    if stamps.size < burst_min:
        return []
    in_window = np.searchsorted(stamps, stamps + window_ns, side="right") - np.arange(stamps.size)
    runs: list[list[int]] = []  # first, last, peak records in one window
    for first in np.flatnonzero(in_window >= burst_min).tolist():
        last, peak = first + int(in_window[first]) - 1, int(in_window[first])
        if runs and first <= runs[-1][1]:
            runs[-1] = [runs[-1][0], max(runs[-1][1], last), max(runs[-1][2], peak)]
        else:
            runs.append([first, last, peak])
    ranked = sorted(runs, key=lambda run: (-run[2], -(run[1] - run[0]), run[0]))
    return [_burst(ordered[first : last + 1]) for first, last, _ in ranked]


def _burst(members: list[LogRecord]) -> Burst:
    nodes = Counter(record.node for record in members)
    top_node = min(nodes.items(), key=lambda item: (-item[1], item[0]))[0]
    worst = max((record.level for record in members), key=level_rank)
    return Burst(members[0].t_ns, members[-1].t_ns, len(members), top_node, worst)
