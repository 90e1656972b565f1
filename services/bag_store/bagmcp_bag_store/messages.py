"""The logic behind get_message_at_time and get_messages_in_range, with bounded output."""

from __future__ import annotations

import numpy as np
from pydantic import JsonValue

from bagmcp_bag_store.deps import BagStoreDeps
from bagmcp_bag_store.errors import ArgumentError
from bagmcp_bag_store.opened import OpenBag, opened
from bagmcp_bag_store.results import MessageAtTime, MessageOut, MessageRange
from bagmcp_shared.bags import RawMessage
from bagmcp_shared.columns import ColumnIndex
from bagmcp_shared.jsonify import fit
from bagmcp_shared.paths import Step, check_steps, extract, format_steps, parse_field_path
from bagmcp_shared.timebase import TimeInput, header_stamp_ns


def message_out(bag: OpenBag, raw: RawMessage, projection: list[tuple[Step, ...]], budget: int) -> MessageOut:
    """One message as answers show it, its JSON within ``budget`` bytes."""
    msg = bag.reader.decode(raw)
    shown: object = {format_steps(p): extract(msg, p) for p in projection} if projection else msg
    header = header_stamp_ns(msg)
    data: JsonValue = fit(shown, budget)
    return MessageOut(time=bag.instant(raw.log_time_ns), header_stamp_s=header / 1e9 if header else None, data=data)


def projection(bag: OpenBag, topic: str, fields: list[str] | None) -> list[tuple[Step, ...]]:
    msgtype = bag.reader.topic_connections(topic)[0].msgtype
    store = bag.reader.decoder.typestore(msgtype)
    steps = [parse_field_path(f) for f in fields or []]
    for s in steps:
        check_steps(store, msgtype, s)
    return steps


def _nearest(bag: OpenBag, topic: str, stamp_ns: int) -> RawMessage:
    summary = bag.topic(topic)
    if not summary.count:
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
        steps = projection(ob, topic, fields)
        stamp_ns = ob.time(time)
        raw = _nearest(ob, topic, stamp_ns)
        return MessageAtTime(
            bag=ob.record.name,
            topic=raw.connection.topic,
            requested=ob.instant(stamp_ns),
            clock="log_time",
            delta_s=(raw.log_time_ns - stamp_ns) / 1e9,
            message=message_out(ob, raw, steps, deps.max_result_bytes),
        )


def _cursor(text: str | None) -> tuple[int, int, int] | None:
    """``time_ns:skip:total``: where the next page starts, how many at that instant were shown, the window's total."""
    if not text:
        return None
    try:
        stamp, skip, total = (int(part) for part in text.split(":"))
    except ValueError as err:
        raise ArgumentError(f"cursor {text!r} is not one this tool returned") from err
    return stamp, skip, total


def _count(ob: OpenBag, index: ColumnIndex | None, topic: str, lo: int, hi: int) -> int:
    """Messages of ``topic`` in [lo, hi]: from the index or the summary when they can tell, else counted."""
    summary = ob.topic(topic)
    first, last = summary.first_ns, summary.last_ns
    if first is None or last is None or (lo <= first and hi >= last):
        return summary.count
    if index is not None and index.columns(topic):
        times = index.read(topic, []).t_ns
        return int(np.searchsorted(times, hi, side="right") - np.searchsorted(times, lo, side="left"))
    return sum(1 for _ in ob.reader.messages([topic], start_ns=lo, stop_ns=hi + 1))


def _page(
    ob: OpenBag, topic: str, steps: list[tuple[Step, ...]], start: tuple[int, int], hi: int, limits: tuple[int, int]
) -> tuple[list[MessageOut], tuple[int, int] | None]:
    """Messages from ``start`` = (time, skip) up to ``hi`` within (max messages, byte budget).

    Returns the page and where the next one starts (None at the end of the window).
    """
    begin, skip = start
    max_messages, budget = limits
    out: list[MessageOut] = []
    used = 0
    run_ts, run = -1, 0
    for index, raw in enumerate(ob.reader.messages([topic], start_ns=begin, stop_ns=hi + 1)):
        if index >= skip:
            item = message_out(ob, raw, steps, budget)
            size = len(item.model_dump_json())
            if len(out) >= max_messages or (out and used + size > budget):
                return out, (raw.log_time_ns, run if run_ts == raw.log_time_ns else 0)
            out.append(item)
            used += size
        run, run_ts = (run + 1, run_ts) if raw.log_time_ns == run_ts else (1, raw.log_time_ns)
    return out, None


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
        name = ob.reader.topic_connections(topic)[0].topic
        steps = projection(ob, name, fields)
        lo = ob.time(start, what="start") if start is not None else ob.start_ns
        hi = ob.time(end, what="end") if end is not None else ob.end_ns
        if lo > hi:
            raise ArgumentError("start must not be after end")
        resume = _cursor(cursor)
        if resume is not None and not lo <= resume[0] <= hi:
            raise ArgumentError("the cursor does not belong to this start/end window")
        total = resume[2] if resume else _count(ob, ColumnIndex.load(deps.files.index_dir(ob.record)), name, lo, hi)
        first = (resume[0], resume[1]) if resume else (lo, 0)
        out, following = _page(ob, name, steps, first, hi, (max_messages, deps.max_result_bytes))
        return MessageRange(
            bag=ob.record.name,
            topic=name,
            start=ob.instant(lo),
            end=ob.instant(hi),
            clock="log_time",
            total=total,
            returned=len(out),
            truncated=following is not None,
            next_cursor=f"{following[0]}:{following[1]}:{total}" if following else None,
            messages=out,
        )
