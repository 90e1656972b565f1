"""The logic behind list_bags, bag_info and describe_topic (catalog and type questions)."""

from __future__ import annotations

from pydantic import JsonValue

from bagmcp_bag_store.deps import BagStoreDeps
from bagmcp_bag_store.errors import ArgumentError
from bagmcp_bag_store.messages import message_out
from bagmcp_bag_store.models import BagRecord
from bagmcp_bag_store.opened import epoch_ns, instant, opened, ready_record
from bagmcp_bag_store.results import (
    BagBrief,
    BagInfo,
    BagList,
    FieldInfo,
    Instant,
    TopicDescription,
    TopicInfo,
)
from bagmcp_shared.paths import field_paths
from bagmcp_shared.units import unit_of

MAX_FIELDS = 120


def _instant(value: JsonValue, start_ns: int) -> Instant | None:
    stamp_ns = epoch_ns(value)
    return instant(stamp_ns, start_ns=start_ns) if stamp_ns is not None else None


def _start_ns(record: BagRecord) -> int:
    return epoch_ns(record.summary_value("start")) or 0


def _brief(record: BagRecord) -> BagBrief:
    topics = record.summary_value("topics")
    count, duration, fmt = (record.summary_value(k) for k in ("message_count", "duration_s", "format"))
    return BagBrief(
        id=record.id,
        name=record.name,
        status=record.status,
        error=record.error,
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
        rate, header_rate = t.get("rate_hz"), t.get("header_rate_hz")
        topics.append(
            TopicInfo(
                name=str(t["name"]),
                type=str(t["type"]),
                count=int(str(t["count"])),
                rate_hz=float(rate) if isinstance(rate, int | float) else None,
                header_rate_hz=float(header_rate) if isinstance(header_rate, int | float) else None,
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


def describe_topic(deps: BagStoreDeps, bag: str, topic: str) -> TopicDescription:
    with opened(deps, bag, need_messages=False) as ob:
        conn = ob.reader.topic_connections(topic)[0]
        store = ob.reader.decoder.typestore(conn.msgtype)
        paths = field_paths(store, conn.msgtype)
        summary = ob.topic(conn.topic)
        first = next(ob.reader.messages([conn.topic]), None)
        sample = message_out(ob, first, [], deps.max_result_bytes // 2) if first else None
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
