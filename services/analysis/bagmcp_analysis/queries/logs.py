"""analyze_logs: ROS 1 and ROS 2 log records, filtered by level, node, text and time, with a summary."""

from __future__ import annotations

from typing import Annotated

from pydantic import BaseModel, Field

from bagmcp_analysis.logs.records import Burst, LogRecord, filter_records, summarize_records
from bagmcp_analysis.reports.logs import BurstOut, LogEntry, LogReport, LogSummaryOut
from bagmcp_kit.arguments import BagRef, Offset, TimeArg
from bagmcp_shared.access import BagAccess, OpenBag
from bagmcp_shared.errors import ArgumentError
from bagmcp_shared.index import RECORD_TYPES, LogRow, decode_logs
from bagmcp_shared.jobs import Progress, spans
from bagmcp_shared.log_levels import level_name

ROS2_LOG = "rcl_interfaces/msg/Log"
ENTRY_BUDGET_BYTES = 12_000


Level = Annotated[str | None, Field(description="DEBUG, INFO, WARN, ERROR, FATAL (or number)")]


class LogParams(BaseModel):
    """The arguments of analyze_logs, in the order the tool lists them."""

    bag: BagRef
    level: Level = None
    min_level: Annotated[str | None, Field(description="this level or worse")] = None
    node: Annotated[str | None, Field(description="node name (or part of it)")] = None
    contains: Annotated[str | None, Field(description="text in the message, any case")] = None
    start: TimeArg | None = None
    end: TimeArg | None = None
    summary: bool = True
    topic: Annotated[str | None, Field(description="default: every log topic")] = None
    offset: Offset = 0
    limit: Annotated[int, Field(ge=1, le=500, description="records to show")] = 50


def log_topics(ob: OpenBag, topic: str | None) -> list[str]:
    if topic is not None:
        name = ob.topic_name(topic)
        if ob.msgtype(name) not in RECORD_TYPES:
            raise ArgumentError(
                f"{name} is {ob.msgtype(name)}, not a log type (rosgraph_msgs/Log, rcl_interfaces/Log, "
                "PX4 logged_messages, ArduPilot MSG or ERR)"
            )
        return [name]
    found = [t.name for t in ob.summary.topics if t.type in RECORD_TYPES and t.count]
    if not found:
        raise ArgumentError(
            f"{ob.name} has no log topic (rosgraph_msgs/Log, rcl_interfaces/msg/Log, PX4 logged_messages, "
            "ArduPilot MSG or ERR)"
        )
    return found


def _rows(ob: OpenBag, topic: str, progress: Progress) -> list[LogRow]:
    indexed = ob.index.logs(topic) if ob.index is not None else None
    if indexed is not None:
        return indexed
    return decode_logs(ob.reader, topic, progress=progress)


def read_records(ob: OpenBag, topics: list[str], progress: Progress) -> tuple[list[LogRecord], int]:
    """Records of every topic in time order, with copies (e.g. /rosout_agg of /rosout) counted once."""
    seen: set[tuple[int, int, str, str]] = set()
    records: list[LogRecord] = []
    duplicates = 0
    for topic, step in zip(topics, spans(progress, len(topics)), strict=True):
        ros2 = ob.msgtype(topic) == ROS2_LOG
        for row in _rows(ob, topic, step):
            key = (row.stamp_ns or row.t_ns, row.level, row.node, row.text)
            if key in seen:
                duplicates += 1
                continue
            seen.add(key)
            level = level_name(row.level, ros2=ros2)
            records.append(LogRecord(row.t_ns, level, row.level, row.node, row.text, row.file, row.function, row.line))
    return sorted(records, key=lambda r: r.t_ns), duplicates


def log_entry(ob: OpenBag, record: LogRecord) -> LogEntry:
    where = f"{record.file}:{record.line}" + (f" ({record.function})" if record.function else "")
    return LogEntry(time=ob.instant(record.t_ns), level=record.level, node=record.node, text=record.text, source=where)


def _burst(ob: OpenBag, burst: Burst) -> BurstOut:
    return BurstOut(
        start=ob.instant(burst.start_ns),
        end=ob.instant(burst.end_ns),
        count=burst.count,
        top_node=burst.top_node,
        worst_level=burst.worst_level,
    )


def _page(ob: OpenBag, records: list[LogRecord], offset: int, limit: int) -> list[LogEntry]:
    entries: list[LogEntry] = []
    used = 0
    for record in records[offset : offset + limit]:
        entry = log_entry(ob, record)
        used += len(entry.model_dump_json())
        if entries and used > ENTRY_BUDGET_BYTES:
            break
        entries.append(entry)
    return entries


def analyze_logs(access: BagAccess, params: LogParams, progress: Progress) -> LogReport:
    with access.open(params.bag) as ob:
        topics = log_topics(ob, params.topic)
        lo, hi = ob.window(params.start, params.end)
        records, duplicates = read_records(ob, topics, progress)
        try:
            matching = filter_records(
                records,
                level=params.level,
                min_level=params.min_level,
                node=params.node,
                contains=params.contains,
                start_ns=lo,
                end_ns=hi,
            )
            summary = summarize_records(matching) if params.summary else None
        except ValueError as err:
            raise ArgumentError(str(err)) from err
        entries = _page(ob, matching, params.offset, params.limit)
        following = params.offset + len(entries)
        notes = [f"{duplicates} records repeated on another log topic were counted once"] if duplicates else []
        return LogReport(
            bag=ob.name,
            topics=topics,
            start=ob.instant(lo),
            end=ob.instant(hi),
            total=len(matching),
            returned=len(entries),
            next_offset=following if following < len(matching) else None,
            entries=entries,
            summary=LogSummaryOut(
                by_level=summary.by_level,
                by_node=summary.by_node,
                first_error=log_entry(ob, summary.first_error) if summary.first_error else None,
                last_error=log_entry(ob, summary.last_error) if summary.last_error else None,
                first_warning=log_entry(ob, summary.first_warning) if summary.first_warning else None,
                bursts=[_burst(ob, b) for b in summary.bursts],
            )
            if summary is not None
            else None,
            notes=notes,
        )


def logs_are_small(access: BagAccess, params: LogParams) -> bool:
    with access.open(params.bag) as ob:
        topics = log_topics(ob, params.topic)
        indexed = ob.index is not None and all(t in ob.index.log_topics() for t in topics)
        return indexed or all(ob.short(t) for t in topics)
