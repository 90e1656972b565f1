"""The catalog: bag records by id, with unique names. Redis in team mode, memory when embedded."""

from __future__ import annotations

import difflib
import threading
from typing import Protocol

import redis

from bagmcp_bag_store.errors import AmbiguousBagError, BagNotFoundError, NameTakenError
from bagmcp_bag_store.models import BagRecord
from bagmcp_shared.errors import StorageError

_PREFIX = "bagmcp:catalog"


class Catalog(Protocol):
    def get(self, bag_id: str) -> BagRecord | None: ...
    def all(self) -> list[BagRecord]: ...
    def put(self, record: BagRecord) -> None: ...
    def claim_name(self, name: str, bag_id: str) -> None:
        """Reserve ``name`` for ``bag_id``; NameTakenError when another bag holds it."""
        ...

    def release_name(self, name: str, bag_id: str) -> None: ...
    def delete(self, bag_id: str) -> None: ...


class MemoryCatalog:
    """In-process catalog for the embedded server."""

    def __init__(self) -> None:
        self._records: dict[str, BagRecord] = {}
        self._names: dict[str, str] = {}
        self._lock = threading.Lock()

    def get(self, bag_id: str) -> BagRecord | None:
        return self._records.get(bag_id)

    def all(self) -> list[BagRecord]:
        return sorted(self._records.values(), key=lambda r: r.name)

    def put(self, record: BagRecord) -> None:
        self._records[record.id] = record

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
        record = self._records.pop(bag_id, None)
        if record is not None:
            self.release_name(record.name, bag_id)


class RedisCatalog:
    """Catalog in Redis: one JSON value per bag, a set of ids, one key per name (SET NX)."""

    def __init__(self, client: redis.Redis) -> None:
        self._redis = client

    @classmethod
    def from_url(cls, url: str) -> RedisCatalog:
        return cls(redis.Redis.from_url(url, socket_connect_timeout=3, socket_timeout=10))

    def get(self, bag_id: str) -> BagRecord | None:
        try:
            raw = self._redis.get(f"{_PREFIX}:bag:{bag_id}")
        except redis.RedisError as err:
            raise StorageError(f"the catalog (Redis) is unreachable: {err}") from err
        return BagRecord.model_validate_json(raw) if isinstance(raw, bytes) else None

    def all(self) -> list[BagRecord]:
        try:
            members = self._redis.smembers(f"{_PREFIX}:ids")
            ids = sorted(m.decode() if isinstance(m, bytes) else str(m) for m in members)
            raws = self._redis.mget([f"{_PREFIX}:bag:{i}" for i in ids]) if ids else []
        except redis.RedisError as err:
            raise StorageError(f"the catalog (Redis) is unreachable: {err}") from err
        records = [BagRecord.model_validate_json(r) for r in raws if isinstance(r, bytes)]
        return sorted(records, key=lambda r: r.name)

    def put(self, record: BagRecord) -> None:
        try:
            with self._redis.pipeline() as pipe:
                pipe.set(f"{_PREFIX}:bag:{record.id}", record.model_dump_json())
                pipe.sadd(f"{_PREFIX}:ids", record.id)
                pipe.execute()
        except redis.RedisError as err:
            raise StorageError(f"the catalog (Redis) is unreachable: {err}") from err

    def claim_name(self, name: str, bag_id: str) -> None:
        key = f"{_PREFIX}:name:{name}"
        try:
            if self._redis.set(key, bag_id, nx=True):
                return
            holder = self._redis.get(key)
        except redis.RedisError as err:
            raise StorageError(f"the catalog (Redis) is unreachable: {err}") from err
        holder_id = holder.decode() if isinstance(holder, bytes) else ""
        if holder_id != bag_id:
            raise NameTakenError(f"a bag named {name!r} exists already ({holder_id}); choose another name")

    def release_name(self, name: str, bag_id: str) -> None:
        key = f"{_PREFIX}:name:{name}"
        holder = self._redis.get(key)
        if isinstance(holder, bytes) and holder.decode() == bag_id:
            self._redis.delete(key)

    def delete(self, bag_id: str) -> None:
        record = self.get(bag_id)
        with self._redis.pipeline() as pipe:
            pipe.delete(f"{_PREFIX}:bag:{bag_id}")
            pipe.srem(f"{_PREFIX}:ids", bag_id)
            pipe.execute()
        if record is not None:
            self.release_name(record.name, bag_id)


def resolve_bag(catalog: Catalog, ref: str) -> BagRecord:
    """A bag by id, name, or unique prefix of either; unknown refs list close matches."""
    ref = ref.strip()
    if (record := catalog.get(ref)) is not None:
        return record
    records = catalog.all()
    exact = [r for r in records if r.name == ref]
    if exact:
        return exact[0]
    matches = [r for r in records if r.id.startswith(ref) or r.name.startswith(ref)] if ref else []
    if len(matches) == 1:
        return matches[0]
    if len(matches) > 1:
        names = ", ".join(f"{r.name} ({r.id})" for r in matches[:10])
        raise AmbiguousBagError(f"{ref!r} matches several bags: {names}; give more of the name or id")
    close = difflib.get_close_matches(ref, [r.name for r in records], n=5, cutoff=0.4)
    hint = f"; did you mean: {', '.join(close)}?" if close else ""
    known = "" if close else f"; {len(records)} bags exist (call list_bags)"
    raise BagNotFoundError(f"no bag called {ref!r}{hint}{known}")
