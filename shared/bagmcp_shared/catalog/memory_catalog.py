"""The in-process catalog of the embedded server."""

from __future__ import annotations

import threading

from bagmcp_shared.catalog.models import BagRecord
from bagmcp_shared.errors import NameTakenError


class MemoryCatalog:
    def __init__(self) -> None:
        self._records: dict[str, BagRecord] = {}
        self._names: dict[str, str] = {}
        self._lock = threading.Lock()

    def get(self, bag_id: str) -> BagRecord | None:
        return self._records.get(bag_id)

    def named(self, name: str) -> BagRecord | None:
        holder = self._names.get(name)
        record = self._records.get(holder) if holder is not None else None
        return record if record is not None and record.name == name else None

    def all(self) -> list[BagRecord]:
        return sorted(self._records.values(), key=lambda r: r.name)

    def add(self, record: BagRecord) -> bool:
        with self._lock:
            return self._records.setdefault(record.id, record) is record

    def replace(self, record: BagRecord) -> bool:
        with self._lock:
            if record.id not in self._records:
                return False
            self._records[record.id] = record
            return True

    def claim_name(self, name: str, bag_id: str) -> None:
        with self._lock:
            holder = self._names.setdefault(name, bag_id)
        if holder != bag_id:
            raise NameTakenError(f"a bag named {name!r} exists already ({holder}); choose another name")

    def release_name(self, name: str, bag_id: str) -> None:
        with self._lock:
            if self._names.get(name) == bag_id:
                del self._names[name]

    def delete(self, bag_id: str) -> None:
        with self._lock:
            record = self._records.pop(bag_id, None)
            if record is not None and self._names.get(record.name) == bag_id:
                del self._names[record.name]
