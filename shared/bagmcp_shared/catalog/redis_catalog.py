"""The team catalog in Redis: one JSON value per bag, a set of ids, one key per name."""

from __future__ import annotations

import redis

from bagmcp_shared.catalog.models import BagRecord
from bagmcp_shared.errors import NameTakenError
from bagmcp_shared.redis_errors import reachable

_PREFIX = "bagmcp:catalog"
# Delete a key only if it still holds the expected value (atomic compare-and-delete).
# Add a record only if its id is new, and list its id in the same step.
_ADD = "if redis.call('set', KEYS[1], ARGV[1], 'NX') then redis.call('sadd', KEYS[2], ARGV[2]) return 1 end return 0"
_RELEASE = "if redis.call('get', KEYS[1]) == ARGV[1] then return redis.call('del', KEYS[1]) else return 0 end"
# The record of the bag holding a name, in one round trip.
_NAMED = (
    f"local id = redis.call('get', KEYS[1]) if id then return redis.call('get', '{_PREFIX}:bag:' .. id) end "
    "return false"
)


def _key(bag_id: str) -> str:
    return f"{_PREFIX}:bag:{bag_id}"


class RedisCatalog:
    def __init__(self, client: redis.Redis) -> None:
        self._redis = client

    def get(self, bag_id: str) -> BagRecord | None:
        with reachable("the catalog"):
            raw = self._redis.get(_key(bag_id))
        return BagRecord.model_validate_json(raw) if isinstance(raw, bytes) else None

    def named(self, name: str) -> BagRecord | None:
        with reachable("the catalog"):
            raw = self._redis.eval(_NAMED, 1, f"{_PREFIX}:name:{name}")
        record = BagRecord.model_validate_json(raw) if isinstance(raw, bytes) else None
        return record if record is not None and record.name == name else None

    def all(self) -> list[BagRecord]:
        with reachable("the catalog"):
            members = self._redis.smembers(f"{_PREFIX}:ids")
            ids = sorted(m.decode() if isinstance(m, bytes) else str(m) for m in members)
            raws = self._redis.mget([_key(i) for i in ids]) if ids else []
        records = [BagRecord.model_validate_json(r) for r in raws if isinstance(r, bytes)]
        return sorted(records, key=lambda r: r.name)

    def add(self, record: BagRecord) -> bool:
        with reachable("the catalog"):
            added = self._redis.eval(_ADD, 2, _key(record.id), f"{_PREFIX}:ids", record.model_dump_json(), record.id)
        return bool(added)

    def replace(self, record: BagRecord) -> bool:
        with reachable("the catalog"):
            return bool(self._redis.set(_key(record.id), record.model_dump_json(), xx=True))

    def claim_name(self, name: str, bag_id: str) -> None:
        key = f"{_PREFIX}:name:{name}"
        with reachable("the catalog"):
            if self._redis.set(key, bag_id, nx=True):
                return
            holder = self._redis.get(key)
        holder_id = holder.decode() if isinstance(holder, bytes) else ""
        if holder_id != bag_id:
            raise NameTakenError(f"a bag named {name!r} exists already ({holder_id}); choose another name")

    def release_name(self, name: str, bag_id: str) -> None:
        with reachable("the catalog"):
            self._redis.eval(_RELEASE, 1, f"{_PREFIX}:name:{name}", bag_id)

    def delete(self, bag_id: str) -> None:
        record = self.get(bag_id)
        with reachable("the catalog"), self._redis.pipeline() as pipe:
            pipe.delete(_key(bag_id))
            pipe.srem(f"{_PREFIX}:ids", bag_id)
            pipe.execute()
        if record is not None:
            self.release_name(record.name, bag_id)
