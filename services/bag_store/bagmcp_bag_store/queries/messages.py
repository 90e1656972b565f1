"""The logic behind get_message_at_time and get_messages_in_range, with bounded output, and their params
models (the tools are declared in tools/message_tools.py; layout=columns is column_range.py)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Annotated, Literal

import numpy as np
from pydantic import BaseModel, Field, JsonValue

from bagmcp_bag_store.queries.page_cursor import Cursor, CursorSigner, PageScope
from bagmcp_bag_store.reports import MessageAtTime, MessageOut, MessageRange, RangeMessage
from bagmcp_kit.arguments import BagRef, Fields, TimeArg, TopicName
from bagmcp_shared.access import BagAccess, OpenBag
from bagmcp_shared.bags import RawMessage
from bagmcp_shared.index import ColumnIndex
from bagmcp_shared.jsonify import fit
from bagmcp_shared.paths import Step, check_steps, extract, format_steps, parse_field_path
from bagmcp_shared.timebase import header_stamp_ns, iso_from_ns


class MessageAtTimeParams(BaseModel):
    bag: BagRef
    topic: TopicName
    time: TimeArg
    fields: Fields = None


class MessageRangeParams(BaseModel):
    bag: BagRef
    topic: TopicName
    start: TimeArg | None = None
    end: TimeArg | None = None
    fields: Fields = None
    max_messages: Annotated[int, Field(ge=1, le=1000, description="page size")] = 20
    cursor: Annotated[str | None, Field(description="next_cursor of the previous page")] = None
    every: Annotated[int, Field(ge=1, description="keep every n-th message")] = 1
    layout: Literal["messages", "columns"] = "messages"
    max_points: Annotated[
        int | None, Field(ge=2, le=5000, description="thin numeric fields to this, extremes kept (columns)")
    ] = None

    @property
    def in_columns(self) -> bool:
        """max_points thins numeric fields, which only columns can do, so it implies them."""
        return self.layout == "columns" or self.max_points is not None


def message_out(bag: OpenBag, raw: RawMessage, projection: list[tuple[Step, ...]], budget: int) -> MessageOut:
    """One message as answers show it, its JSON within ``budget`` bytes."""
    msg = bag.reader.decode(raw)
    shown: object = {format_steps(p): extract(msg, p) for p in projection} if projection else msg
    header = header_stamp_ns(msg)
    data: JsonValue = fit(shown, budget)
    return MessageOut(time=bag.instant(raw.log_time_ns), header_stamp_s=header / 1e9 if header else None, data=data)


def time_base(bag: OpenBag) -> str:
    """The one statement of what a range's offsets count from, so each message carries only its offset."""
    return f"log time, s from the bag start {iso_from_ns(bag.start_ns)} (epoch {bag.start_ns / 1e9:.6f} s)"


def range_message(bag: OpenBag, raw: RawMessage, projection: list[tuple[Step, ...]], budget: int) -> RangeMessage:
    """One message of a range: its offset and data (header stamps are in the data, where asked for)."""
    msg = bag.reader.decode(raw)
    shown: object = {format_steps(p): extract(msg, p) for p in projection} if projection else msg
    return RangeMessage(offset_s=round((raw.log_time_ns - bag.start_ns) / 1e9, 9), data=fit(shown, budget))


def projection(bag: OpenBag, topic: str, fields: list[str] | None) -> list[tuple[Step, ...]]:
    msgtype = bag.reader.topic_connections(topic)[0].msgtype
    store = bag.reader.decoder.typestore(msgtype)
    steps = [parse_field_path(f) for f in fields or []]
    for s in steps:
        check_steps(store, msgtype, s)
    return steps


def get_message_at_time(access: BagAccess, params: MessageAtTimeParams, *, budget_bytes: int) -> MessageAtTime:
    with access.open(params.bag) as ob:
        steps = projection(ob, params.topic, params.fields)
        stamp_ns = ob.time(params.time)
        raw = ob.nearest(params.topic, stamp_ns)
        return MessageAtTime(
            bag=ob.record.name,
            topic=raw.connection.topic,
            requested=ob.instant(stamp_ns),
            clock="log_time",
            delta_s=(raw.log_time_ns - stamp_ns) / 1e9,
            message=message_out(ob, raw, steps, budget_bytes),
        )


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


@dataclass(frozen=True)
class _Limits:
    max_messages: int
    budget_bytes: int
    every: int


def _page(
    ob: OpenBag, topic: str, steps: list[tuple[Step, ...]], first: Cursor, hi: int, limits: _Limits
) -> tuple[list[RangeMessage], Cursor | None]:
    """Messages from ``first`` up to ``hi`` within the limits (every ``every``-th message of the window).

    Returns the page and where the next one starts (None at the end of the window).
    """
    out: list[RangeMessage] = []
    used = 0
    run_ts, run = -1, 0
    position = first.position
    for index, raw in enumerate(ob.reader.messages([topic], start_ns=first.stamp_ns, stop_ns=hi + 1)):
        if index >= first.skip:
            if position % limits.every == 0:
                item = range_message(ob, raw, steps, limits.budget_bytes)
                size = len(item.model_dump_json())
                if len(out) >= limits.max_messages or (out and used + size > limits.budget_bytes):
                    skip = run if run_ts == raw.log_time_ns else 0
                    return out, Cursor(raw.log_time_ns, skip, first.total, position)
                out.append(item)
                used += size
            position += 1
        run, run_ts = (run + 1, run_ts) if raw.log_time_ns == run_ts else (1, raw.log_time_ns)
    return out, None


def get_messages_in_range(
    access: BagAccess, params: MessageRangeParams, *, budget_bytes: int, signer: CursorSigner
) -> MessageRange:
    every = params.every
    with access.open(params.bag) as ob:
        name = ob.topic_name(params.topic)
        steps = projection(ob, name, params.fields)
        lo, hi = ob.window(params.start, params.end)
        scope = PageScope(ob.record.id, name, lo, hi, every)
        resume = signer.parse(params.cursor, scope)
        first = resume or Cursor(lo, 0, _count(ob, ob.index, name, lo, hi))
        out, following = _page(ob, name, steps, first, hi, _Limits(params.max_messages, budget_bytes, every))
        return MessageRange(
            bag=ob.record.name,
            topic=name,
            start=ob.instant(lo),
            end=ob.instant(hi),
            clock="log_time",
            time_base=time_base(ob),
            total=first.total,
            returned=len(out),
            truncated=following is not None,
            next_cursor=signer.dump(following, scope) if following else None,
            messages=out,
        )
