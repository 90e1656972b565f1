"""The declarations of the catalog and type questions: list_bags, bag_info, describe_topic (short tools; their
params models live beside their queries in queries/catalog_queries.py)."""

from __future__ import annotations

from bagmcp_bag_store.queries.catalog_queries import (
    BagParams,
    ListBagsParams,
    TopicParams,
    bag_info,
    describe_topic,
    list_bags,
)
from bagmcp_bag_store.reports import BagInfo, BagList, TopicDescription
from bagmcp_bag_store.tools.store import Reading
from bagmcp_kit.declared import Declared
from bagmcp_shared.wording import counted

LIST_BAGS = Declared[Reading, ListBagsParams, BagList](
    "list_bags",
    "Bags in the store: status (ready, ingesting, or failed and why), format, duration, counts. Call this "
    'first. Example: name="husky".',
    ListBagsParams,
    BagList,
    lambda reading, p, _: list_bags(reading.access.catalog, p),
    lambda r: f"{counted(r.total, 'bag')}; showing {len(r.bags)} from {r.offset}",
    long=False,
)
BAG_INFO = Declared[Reading, BagParams, BagInfo](
    "bag_info",
    "One bag: format, size, start/end, duration, each topic's type, count and rate (odd rates explained). "
    'Example: bag="run1".',
    BagParams,
    BagInfo,
    lambda reading, p, _: bag_info(reading.access.catalog, p),
    lambda r: f"{r.name}: {r.message_count} messages on {len(r.topics)} topics over {r.duration_s:.3f} s",
    long=False,
)
DESCRIBE_TOPIC = Declared[Reading, TopicParams, TopicDescription](
    "describe_topic",
    "A topic's field paths with types and units, plus its first message as a sample; use the paths in "
    '`fields` and plots. Example: topic="/odom".',
    TopicParams,
    TopicDescription,
    lambda reading, p, _: describe_topic(reading.access, p, budget_bytes=reading.budget_bytes),
    lambda r: f"{r.topic} ({r.type}): {r.count} messages, {len(r.fields)} fields",
    long=False,
)
