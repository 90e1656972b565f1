"""The logic behind list_bags, bag_info and describe_topic (catalog and type questions), and their params
models (the tools are declared in tools/catalog_tools.py)."""

from __future__ import annotations

from typing import Annotated

from pydantic import BaseModel, Field

from bagmcp_bag_store.queries.messages import message_out
from bagmcp_bag_store.reports import BagBrief, BagInfo, BagList, FieldInfo, TopicDescription, TopicInfo
from bagmcp_kit.arguments import BagRef, Offset, TopicName
from bagmcp_shared.access import BagAccess
from bagmcp_shared.carry import carried
from bagmcp_shared.catalog import BagRecord, Catalog, TopicStats, ready_record
from bagmcp_shared.errors import ArgumentError
from bagmcp_shared.paths import field_paths
from bagmcp_shared.timebase import Instant
from bagmcp_shared.units import unit_of

MAX_FIELDS = 120


class ListBagsParams(BaseModel):
    name: Annotated[str | None, Field(description="part of the name")] = None
    tag: Annotated[str | None, Field(description="with this tag")] = None
    offset: Offset = 0
    limit: Annotated[int, Field(ge=1, le=500, description="page size")] = 50


class BagParams(BaseModel):
    bag: BagRef


class TopicParams(BaseModel):
    bag: BagRef
    topic: TopicName


def _instant(stamp_ns: int | None, start_ns: int) -> Instant | None:
    return Instant.of(stamp_ns, start_ns=start_ns) if stamp_ns is not None else None


def _brief(record: BagRecord) -> BagBrief:
    summary = record.summary
    start_ns = summary.start_ns if summary else None
    return BagBrief(
        id=record.id,
        name=record.name,
        status=record.status,
        error=record.error,
        progress=record.progress if record.status == "ingesting" else None,
        format=summary.format if summary else None,
        size_bytes=record.size_bytes,
        duration_s=summary.duration_s if summary else None,
        message_count=summary.message_count if summary else None,
        topic_count=len(summary.topics) if summary else None,
        start=_instant(start_ns, start_ns or 0),
        tags=record.tags,
    )


def list_bags(catalog: Catalog, params: ListBagsParams) -> BagList:
    """``params`` may come unvalidated (the REST route builds it as asked), hence the bounds check."""
    name, tag, offset, limit = params.name, params.tag, params.offset, params.limit
    if offset < 0 or not 1 <= limit <= 500:
        raise ArgumentError("offset must be >= 0 and limit between 1 and 500")
    records = [r for r in catalog.all() if (not name or name.lower() in r.name.lower()) and (not tag or tag in r.tags)]
    page = records[offset : offset + limit]
    following = offset + limit if offset + limit < len(records) else None
    return BagList(bags=[_brief(r) for r in page], total=len(records), offset=offset, next_offset=following)


ODD_SPAN_NS = 1_000_000  # messages closer together than this were written in one go, not streamed


def topic_note(topic: TopicStats) -> str | None:
    """A sentence explaining a rate that would mislead (many messages stamped within a moment)."""
    if topic.count < 2 or topic.first_ns is None or topic.last_ns is None:
        return None
    span_ns = topic.last_ns - topic.first_ns
    if span_ns >= ODD_SPAN_NS:
        return None
    rate = f"{topic.rate_hz:,.0f} Hz rate" if topic.rate_hz else "rate"
    return (
        f"all {topic.count} messages are stamped within {span_ns / 1000:,.1f} µs (written in one batch), "
        f"so the {rate} says nothing about how often they were published"
    )


def _topic_info(topic: TopicStats, start_ns: int) -> TopicInfo:
    first, last = _instant(topic.first_ns, start_ns), _instant(topic.last_ns, start_ns)
    return carried(TopicInfo, topic, note=topic_note(topic), first=first, last=last)


def bag_info(catalog: Catalog, params: BagParams) -> BagInfo:
    record = ready_record(catalog, params.bag)
    summary = record.summary
    assert summary is not None  # a ready bag has its summary
    start_ns = summary.start_ns or 0
    return carried(
        BagInfo,
        record,
        summary,
        start=_instant(summary.start_ns, start_ns),
        end=_instant(summary.end_ns, start_ns),
        topics=[_topic_info(t, start_ns) for t in summary.topics],
    )


def describe_topic(access: BagAccess, params: TopicParams, *, budget_bytes: int) -> TopicDescription:
    with access.open(params.bag, need_messages=False) as ob:
        conn = ob.reader.topic_connections(params.topic)[0]
        store = ob.reader.decoder.typestore(conn.msgtype)
        paths = field_paths(store, conn.msgtype)
        stated = ob.reader.decoder.units(conn.msgtype)
        stats = ob.topic(conn.topic)
        first = next(ob.reader.messages([conn.topic]), None)
        sample = message_out(ob, first, [], budget_bytes // 2) if first else None
        return TopicDescription(
            bag=ob.name,
            topic=conn.topic,
            type=conn.msgtype,
            count=stats.count,
            rate_hz=stats.rate_hz,
            fields=[FieldInfo(path=p, type=t, unit=stated.get(p) or unit_of(p)) for p, t in paths[:MAX_FIELDS]],
            fields_truncated=len(paths) > MAX_FIELDS,
            sample=sample.data if sample else None,
            sample_time=sample.time if sample else None,
        )
