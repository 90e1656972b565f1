"""Bag access for queries: resolve what the caller calls a bag, check it is ready, open it from the
bounded cache, and answer time questions about it."""

from __future__ import annotations

from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from functools import cached_property, partial

from bagmcp_shared.access.files import BagFiles
from bagmcp_shared.access.readers import ReaderCache
from bagmcp_shared.bags import BagReader, RawMessage
from bagmcp_shared.catalog import BagRecord, Catalog, CatalogSummary, TopicStats, ready_record, resolve_bag
from bagmcp_shared.errors import ArgumentError, BagmcpError, DamagedBagError, TimeError, TopicNotFoundError
from bagmcp_shared.index import ColumnIndex
from bagmcp_shared.timebase import Instant, TimeInput, iso_from_ns, parse_time

SHORT_TOPIC = 5_000  # messages decoded inline, without a job


@dataclass(frozen=True)
class _Catalogued:
    """Times and name of a ready bag, from its record and catalog summary."""

    record: BagRecord
    summary: CatalogSummary

    @property
    def start_ns(self) -> int:
        return self.summary.start_ns or 0

    @property
    def end_ns(self) -> int:
        return self.summary.end_ns or 0

    @property
    def name(self) -> str:
        return self.record.name


@dataclass(frozen=True)
class KnownBag(_Catalogued):
    """What the catalog knows about a ready bag: its record, summary and (when built) columnar index."""

    index: ColumnIndex | None


@dataclass(frozen=True)
class OpenBag(_Catalogued):
    """A ready bag, open for reading, with its catalog summary and (when built) columnar index.

    The index is opened when a question first reads it, not with the bag: in team mode opening it fetches
    its manifest from the object store, a round trip a point read (which reads no index) would wait for."""

    reader: BagReader
    open_index: Callable[[], ColumnIndex | None] = field(repr=False, compare=False)

    @cached_property
    def index(self) -> ColumnIndex | None:
        return self.open_index()

    def topic(self, name: str) -> TopicStats:
        """Counts and bounds of a topic (leading slash optional) from the catalog."""
        found = self.summary.topic(name)
        if found is None:
            self.reader.topic_connections(name)  # raises with the list of topics
            raise TopicNotFoundError(f"topic {name!r} is not in {self.record.name}")
        return found

    def topic_name(self, name: str) -> str:
        """The topic's name as the bag spells it (the caller may leave out or add a leading slash)."""
        return self.reader.topic_connections(name)[0].topic

    def msgtype(self, topic: str) -> str:
        return self.reader.topic_connections(topic)[0].msgtype

    def indexed(self, topic: str) -> bool:
        """Whether the columnar index holds columns of ``topic``."""
        return self.index is not None and bool(self.index.columns(topic))

    def short(self, topic: str) -> bool:
        """Whether ``topic`` is short enough to decode while a caller waits (no job needed)."""
        return self.topic(topic).count <= SHORT_TOPIC

    def nearest(self, topic: str, stamp_ns: int) -> RawMessage:
        """The message of ``topic`` whose log time is nearest ``stamp_ns``, reading only around it: a window of
        half an average period either side (one message of a regular topic below 500 Hz, where the 1 ms floor
        starts; the nearest in a window that holds any is the nearest of all), four times wider while it holds
        none. Two periods either side read three or four: a cold image read from the object store fetched 16 MB
        where one 2 MB chunk held the answer. A window over the whole bag that holds none is a damaged bag (the
        catalog counts messages the file no longer gives), not a search without end."""
        stats = self.topic(topic)
        if not stats.count:
            raise ArgumentError(f"topic {topic} has no messages in bag {self.record.name}")
        radius = max(max(self.end_ns - self.start_ns, 1) // stats.count // 2, 1_000_000)
        while True:
            window = list(self.reader.messages([topic], start_ns=stamp_ns - radius, stop_ns=stamp_ns + radius + 1))
            if window:
                return min(window, key=lambda m: abs(m.log_time_ns - stamp_ns))
            if stamp_ns - radius <= self.start_ns and stamp_ns + radius >= self.end_ns:
                raise DamagedBagError(
                    f"bag {self.record.name}: the catalog counts {stats.count:,} messages of {topic}, but the bag "
                    "gives none; it may have been damaged since it was ingested: delete it and upload it again"
                )
            radius *= 4

    def instant(self, stamp_ns: int) -> Instant:
        return Instant.of(stamp_ns, start_ns=self.start_ns)

    def time(self, value: TimeInput, *, what: str = "time") -> int:
        """Parse a caller's time and check that it lies inside the bag."""
        stamp_ns = parse_time(value, start_ns=self.start_ns)
        if not self.start_ns <= stamp_ns <= self.end_ns:
            duration = (self.end_ns - self.start_ns) / 1e9
            raise TimeError(
                f"{what} {value!r} is outside the bag {self.record.name}, which spans 0 .. {duration:.3f} s "
                f"from its start ({iso_from_ns(self.start_ns)} .. {iso_from_ns(self.end_ns)})"
            )
        return stamp_ns

    def window(self, start: TimeInput | None, end: TimeInput | None) -> tuple[int, int]:
        """The caller's [start, end] in epoch ns; the whole bag where a bound is omitted."""
        lo = self.time(start, what="start") if start is not None else self.start_ns
        hi = self.time(end, what="end") if end is not None else self.end_ns
        if lo > hi:
            raise ArgumentError(f"start ({start}) must not be after end ({end})")
        return lo, hi


class BagAccess:
    """What a query needs to reach a bag: the catalog, the bag's local files, the opened-bag cache."""

    def __init__(self, catalog: Catalog, files: BagFiles, *, cache: ReaderCache | None = None) -> None:
        self.catalog = catalog
        self.files = files
        self.cache = cache if cache is not None else ReaderCache()  # an empty cache is falsy

    def record(self, ref: str) -> BagRecord:
        return resolve_bag(self.catalog, ref)

    def close(self) -> None:
        """Close the readers the cache keeps open (the process, or a test, is done with this access)."""
        self.cache.close()

    def ready(self, ref: str) -> BagRecord:
        return ready_record(self.catalog, ref)

    def warm(self, bag_id: str) -> bool:
        """Open a just-ingested bag (reader and index) into the cache while it has room for another bag, so
        the first question about it finds it open; False when the cache is full or the bag cannot be read."""
        if len(self.cache) >= self.cache.max_bags:
            return False
        try:
            with self.open(bag_id, need_messages=False) as bag:
                bag.index  # noqa: B018 (the index opened too: the first question may read it)
            return True
        except BagmcpError:
            return False

    @contextmanager
    def open(self, ref: str, *, need_messages: bool = True) -> Iterator[OpenBag]:
        """A ready bag, open for reading. Questions about time need messages; questions about types do not."""
        record = self.ready(ref)
        summary = record.summary
        if summary is None or ((summary.start_ns is None or summary.end_ns is None) and need_messages):
            raise TimeError(f"bag {record.name} has no messages")
        path, opener = self.files.reader_for(record)
        index = partial(self.cache.index, record.id, path, lambda: ColumnIndex.open(self.files.index_locator(record)))
        with self.cache.reader(record.id, path, opener) as reader:
            yield OpenBag(record, summary, reader, index)
