"""The logic behind list_bags, bag_info, describe_topic, get_message_at_time, get_messages_in_range."""

from __future__ import annotations

import json

from pydantic import JsonValue

from bagmcp_bag_store.deps import BagStoreDeps
from bagmcp_bag_store.errors import ArgumentError
from bagmcp_bag_store.models import BagRecord
from bagmcp_bag_store.opened import OpenBag, opened, ready_record
from bagmcp_bag_store.results import (
    BagBrief,
    BagInfo,
    BagList,
    FieldInfo,
    Instant,
    MessageAtTime,
    MessageOut,
    MessageRange,
    TopicDescription,
    TopicInfo,
)
from bagmcp_shared.bags import RawMessage
from bagmcp_shared.jsonify import to_json
from bagmcp_shared.paths import Step, check_steps, extract, field_paths, format_steps, parse_field_path
from bagmcp_shared.timebase import TimeInput, header_stamp_ns
from bagmcp_shared.units import unit_of

MAX_FIELDS = 120


def _instant(value: JsonValue, start_ns: int) -> Instant | None:
    if not isinstance(value, dict) or not isinstance(value.get("epoch_ns"), int):
        return None
    stamp_ns = value["epoch_ns"]
    assert isinstance(stamp_ns, int)
    return Instant(offset_s=round((stamp_ns - start_ns) / 1e9, 9), stamp_s=stamp_ns / 1e9, iso=str(value.get("iso")))


def _start_ns(record: BagRecord) -> int:
    start = record.summary_value("start")
    stamp = start.get("epoch_ns") if isinstance(start, dict) else None
    return stamp if isinstance(stamp, int) else 0


def _brief(record: BagRecord) -> BagBrief:
    topics = record.summary_value("topics")
    count, duration, fmt = (record.summary_value(k) for k in ("message_count", "duration_s", "format"))
    return BagBrief(
        id=record.id,
        name=record.name,
        status=record.status,
        format=str(fmt) if fmt else None,
        size_bytes=record.size_bytes,
        duration_s=float(duration) if isinstance(duration, int | float) else None,
        message_count=count if isinstance(count, int) else None,
        topic_count=len(topics) if isinstance(topics, list) else None,
        start=_instant(record.summary_value("start"), _start_ns(record)),
        tags=record.tags,
    )


def list_bags(
    deps: BagStoreDeps, *, name: str | None = None, tag: str | None = None, offset: int = 0, limit: int = 50
) -> BagList:
    if offset < 0 or not 1 <= limit <= 500:
        raise ArgumentError("offset must be >= 0 and limit between 1 and 500")
    records = [
        r for r in deps.catalog.all() if (not name or name.lower() in r.name.lower()) and (not tag or tag in r.tags)
    ]
    page = records[offset : offset + limit]
    following = offset + limit if offset + limit < len(records) else None
    return BagList(bags=[_brief(r) for r in page], total=len(records), offset=offset, next_offset=following)


def bag_info(deps: BagStoreDeps, bag: str) -> BagInfo:
    record = ready_record(deps, bag)
    start_ns = _start_ns(record)
    topics_raw = record.summary_value("topics")
    topics = []
    for t in topics_raw if isinstance(topics_raw, list) else []:
        assert isinstance(t, dict)
        rate = t.get("rate_hz")
        topics.append(
            TopicInfo(
                name=str(t["name"]),
                type=str(t["type"]),
                count=int(str(t["count"])),
                rate_hz=float(rate) if isinstance(rate, int | float) else None,
                first=_instant(t.get("first"), start_ns),
                last=_instant(t.get("last"), start_ns),
            )
        )
    notes = record.summary_value("notes")
    duration = record.summary_value("duration_s")
    return BagInfo(
        id=record.id,
        name=record.name,
        status=record.status,
        format=str(record.summary_value("format")),
        size_bytes=record.size_bytes,
        sha256=record.sha256,
        message_count=sum(t.count for t in topics),
        duration_s=float(duration) if isinstance(duration, int | float) else 0.0,
        start=_instant(record.summary_value("start"), start_ns),
        end=_instant(record.summary_value("end"), start_ns),
        topics=topics,
        notes=[str(n) for n in notes] if isinstance(notes, list) else [],
    )


def _message_out(bag: OpenBag, raw: RawMessage, projection: list[tuple[Step, ...]]) -> MessageOut:
    msg = bag.reader.decode(raw)
    if projection:
        data: JsonValue = {format_steps(p): to_json(extract(msg, p)) for p in projection}
    else:
        data = to_json(msg)
    header = header_stamp_ns(msg)
    return MessageOut(time=bag.instant(raw.log_time_ns), header_stamp_s=header / 1e9 if header else None, data=data)


def _projection(bag: OpenBag, topic: str, fields: list[str] | None) -> list[tuple[Step, ...]]:
    msgtype = bag.reader.topic_connections(topic)[0].msgtype
    store = bag.reader.decoder.typestore(msgtype)
    steps = [parse_field_path(f) for f in fields or []]
    for s in steps:
        check_steps(store, msgtype, s)
    return steps


def describe_topic(deps: BagStoreDeps, bag: str, topic: str) -> TopicDescription:
    with opened(deps, bag) as ob:
        conn = ob.reader.topic_connections(topic)[0]
        store = ob.reader.decoder.typestore(conn.msgtype)
        paths = field_paths(store, conn.msgtype)
        summary = ob.reader.summary().topic(conn.topic)
        assert summary is not None
        first = next(ob.reader.messages([conn.topic]), None)
        sample = _message_out(ob, first, []) if first else None
        return TopicDescription(
            bag=ob.record.name,
            topic=conn.topic,
            type=conn.msgtype,
            count=summary.count,
            rate_hz=summary.rate_hz,
            fields=[FieldInfo(path=p, type=t, unit=unit_of(p)) for p, t in paths[:MAX_FIELDS]],
            fields_truncated=len(paths) > MAX_FIELDS,
            sample=sample.data if sample else None,
            sample_time=sample.time if sample else None,
        )


def _nearest(bag: OpenBag, topic: str, stamp_ns: int) -> RawMessage:
    summary = bag.reader.summary().topic(topic)
    if summary is None or not summary.count:
        raise ArgumentError(f"topic {topic} has no messages in bag {bag.record.name}")
    span = max(bag.end_ns - bag.start_ns, 1)
    radius = max(2 * span // summary.count, 1_000_000)
    while True:
        window = list(bag.reader.messages([topic], start_ns=stamp_ns - radius, stop_ns=stamp_ns + radius + 1))
        if window:
            return min(window, key=lambda m: abs(m.log_time_ns - stamp_ns))
        radius *= 4


def get_message_at_time(
    deps: BagStoreDeps, bag: str, topic: str, time: TimeInput, fields: list[str] | None = None
) -> MessageAtTime:
    with opened(deps, bag) as ob:
        projection = _projection(ob, topic, fields)
        stamp_ns = ob.time(time)
        raw = _nearest(ob, topic, stamp_ns)
        return MessageAtTime(
            bag=ob.record.name,
            topic=raw.connection.topic,
            requested=ob.instant(stamp_ns),
            clock="log_time",
            delta_s=(raw.log_time_ns - stamp_ns) / 1e9,
            message=_message_out(ob, raw, projection),
        )


def _cursor(text: str | None) -> tuple[int, int] | None:
    if not text:
        return None
    try:
        stamp, skip = text.split(":")
        return int(stamp), int(skip)
    except ValueError as err:
        raise ArgumentError(f"cursor {text!r} is not one this tool returned") from err


def _page(
    ob: OpenBag,
    topic: str,
    projection: list[tuple[Step, ...]],
    begin: int,
    skip: int,
    hi: int,
    max_messages: int,
    budget: int,
) -> tuple[list[MessageOut], int, str | None]:
    """Messages from ``begin`` (skipping ``skip`` at that instant) within the count and byte budget.

    Returns the page, how many messages the rest of the window holds, and the next cursor.
    """
    out: list[MessageOut] = []
    used = seen = 0
    run_ts, run = -1, 0
    following: str | None = None
    for index, raw in enumerate(ob.reader.messages([topic], start_ns=begin, stop_ns=hi + 1)):
        seen += 1
        if index >= skip and following is None:
            item = _message_out(ob, raw, projection)
            size = len(json.dumps(item.model_dump(), default=str))
            if len(out) < max_messages and (not out or used + size <= budget):
                out.append(item)
                used += size
            else:
                following = f"{raw.log_time_ns}:{run if run_ts == raw.log_time_ns else 0}"
                continue
        if following is None:
            run, run_ts = (run + 1, run_ts) if raw.log_time_ns == run_ts else (1, raw.log_time_ns)
    return out, seen, following


def get_messages_in_range(
    deps: BagStoreDeps,
    bag: str,
    topic: str,
    start: TimeInput | None = None,
    end: TimeInput | None = None,
    fields: list[str] | None = None,
    max_messages: int = 20,
    cursor: str | None = None,
) -> MessageRange:
    if not 1 <= max_messages <= 1000:
        raise ArgumentError("max_messages must be between 1 and 1000")
    with opened(deps, bag) as ob:
        projection = _projection(ob, topic, fields)
        lo = ob.time(start, what="start") if start is not None else ob.start_ns
        hi = ob.time(end, what="end") if end is not None else ob.end_ns
        if lo > hi:
            raise ArgumentError("start must not be after end")
        begin, skip = _cursor(cursor) or (lo, 0)
        if not lo <= begin <= hi:
            raise ArgumentError("the cursor does not belong to this start/end window")
        out, seen, following = _page(ob, topic, projection, begin, skip, hi, max_messages, deps.max_result_bytes)
        before = sum(1 for _ in ob.reader.messages([topic], start_ns=lo, stop_ns=begin)) if begin > lo else 0
        return MessageRange(
            bag=ob.record.name,
            topic=topic,
            start=ob.instant(lo),
            end=ob.instant(hi),
            clock="log_time",
            total=before + seen,
            returned=len(out),
            truncated=following is not None,
            next_cursor=following,
            messages=out,
        )
