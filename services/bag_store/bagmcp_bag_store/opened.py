"""Opening a catalogued bag for a query: resolve the reference, check readiness, time helpers."""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass

from pydantic import JsonValue

from bagmcp_bag_store.catalog import resolve_bag
from bagmcp_bag_store.deps import BagStoreDeps
from bagmcp_bag_store.errors import BagNotReadyError
from bagmcp_bag_store.models import BagRecord
from bagmcp_bag_store.results import Instant
from bagmcp_shared.bags import BagReader, TopicSummary, open_bag
from bagmcp_shared.errors import TimeError, TopicNotFoundError
from bagmcp_shared.timebase import Stamp, TimeInput, iso_from_ns, parse_time


def epoch_ns(value: JsonValue) -> int | None:
    """The ``epoch_ns`` of an instant as ingest stored it (``{"iso", "epoch_s", "epoch_ns"}``)."""
    stamp = value.get("epoch_ns") if isinstance(value, dict) else None
    return stamp if isinstance(stamp, int) else None


def instant(stamp_ns: int, *, start_ns: int) -> Instant:
    stamp = Stamp.of(stamp_ns, start_ns=start_ns)
    return Instant(offset_s=stamp.offset_s, stamp_s=stamp.stamp_s, iso=stamp.iso)


def catalog_topics(record: BagRecord) -> dict[str, TopicSummary]:
    """The topics as ingest recorded them (no need to read the bag for counts and bounds)."""
    topics = record.summary_value("topics")
    found = {}
    for t in topics if isinstance(topics, list) else []:
        if isinstance(t, dict) and isinstance(t.get("count"), int):
            name = str(t["name"])
            found[name] = TopicSummary(
                name, str(t["type"]), int(str(t["count"])), epoch_ns(t.get("first")), epoch_ns(t.get("last"))
            )
    return found


@dataclass(frozen=True)
class OpenBag:
    record: BagRecord
    reader: BagReader
    start_ns: int
    end_ns: int

    def topic(self, name: str) -> TopicSummary:
        """Counts and bounds of a topic (leading slash optional) from the catalog."""
        wanted = name.lstrip("/")
        found = next((t for n, t in catalog_topics(self.record).items() if n.lstrip("/") == wanted), None)
        if found is None:
            self.reader.topic_connections(name)  # raises with the list of topics
            raise TopicNotFoundError(f"topic {name!r} is not in {self.record.name}")
        return found

    def instant(self, stamp_ns: int) -> Instant:
        return instant(stamp_ns, start_ns=self.start_ns)

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


def ready_record(deps: BagStoreDeps, bag: str) -> BagRecord:
    record = resolve_bag(deps.catalog, bag)
    if record.status == "ingesting":
        raise BagNotReadyError(f"bag {record.name} is still being ingested; try again in a few seconds")
    if record.status == "failed":
        raise BagNotReadyError(f"bag {record.name} could not be ingested: {record.error}")
    return record


@contextmanager
def opened(deps: BagStoreDeps, bag: str, *, need_messages: bool = True) -> Iterator[OpenBag]:
    """A ready bag, open for reading. Questions about time need messages; questions about types do not."""
    record = ready_record(deps, bag)
    start, end = epoch_ns(record.summary_value("start")), epoch_ns(record.summary_value("end"))
    if (start is None or end is None) and need_messages:
        raise TimeError(f"bag {record.name} has no messages")
    with open_bag(deps.files.path_for(record)) as reader:
        yield OpenBag(record, reader, start or 0, end or 0)
