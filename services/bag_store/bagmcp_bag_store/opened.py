"""Opening a catalogued bag for a query: resolve the reference, check readiness, time helpers."""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass

from bagmcp_bag_store.catalog import resolve_bag
from bagmcp_bag_store.deps import BagStoreDeps
from bagmcp_bag_store.errors import BagNotReadyError
from bagmcp_bag_store.models import BagRecord
from bagmcp_bag_store.results import Instant
from bagmcp_shared.bags import BagReader, open_bag
from bagmcp_shared.errors import TimeError
from bagmcp_shared.timebase import Stamp, TimeInput, iso_from_ns, parse_time


@dataclass(frozen=True)
class OpenBag:
    record: BagRecord
    reader: BagReader
    start_ns: int
    end_ns: int

    def instant(self, stamp_ns: int) -> Instant:
        stamp = Stamp.of(stamp_ns, start_ns=self.start_ns)
        return Instant(offset_s=stamp.offset_s, stamp_s=stamp.stamp_s, iso=stamp.iso)

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
def opened(deps: BagStoreDeps, bag: str) -> Iterator[OpenBag]:
    record = ready_record(deps, bag)
    with open_bag(deps.files.path_for(record)) as reader:
        summary = reader.summary()
        if summary.start_ns is None or summary.end_ns is None:
            raise TimeError(f"bag {record.name} has no messages")
        yield OpenBag(record, reader, summary.start_ns, summary.end_ns)
