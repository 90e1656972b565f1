"""Where token records live: a JSON file under the data directory (embedded) or Redis (team)."""

from __future__ import annotations

import json
import os
import tempfile
import threading
from pathlib import Path
from typing import Protocol

import redis

from bagmcp_gateway.access.tokens.models import TokenRecord
from bagmcp_shared.errors import ArgumentError
from bagmcp_shared.redis_errors import reachable

_KEY = "bagmcp:token:"
_BY_HASH = "bagmcp:token-hash:"


class TokenStore(Protocol):
    def add(self, record: TokenRecord) -> None:
        """Store a new token; ArgumentError when the name is taken."""
        ...

    def by_hash(self, digest: str) -> TokenRecord | None:
        """The record stored under this hash (the caller still compares the hashes in constant time)."""
        ...

    def all(self) -> list[TokenRecord]: ...
    def revoke(self, name: str) -> bool:
        """Remove the token; False when no token has that name."""
        ...


class FileTokenStore:
    """Tokens of an embedded server in one JSON file (mode 600), rewritten atomically.

    Read through: the file is parsed again whenever it changed (another process, `bagmcp token`, may
    have rewritten it), so tokens made or revoked while a server runs count at its next lookup."""

    def __init__(self, path: Path) -> None:
        self._path = path
        self._lock = threading.Lock()
        self._version: tuple[int, int, int] | None = None
        self._records: dict[str, TokenRecord] = {}

    def _read(self) -> dict[str, TokenRecord]:
        try:
            stat = self._path.stat()
            version = (stat.st_ino, stat.st_mtime_ns, stat.st_size)
            if version != self._version:
                raw = json.loads(self._path.read_text())
                self._records = {name: TokenRecord.model_validate(body) for name, body in raw.items()}
                self._version = version
        except FileNotFoundError:
            self._version, self._records = None, {}
        except (OSError, ValueError) as err:
            raise ArgumentError(f"the token file {self._path} cannot be read ({err})") from err
        return dict(self._records)

    def _write(self, records: dict[str, TokenRecord]) -> None:
        self._path.parent.mkdir(parents=True, exist_ok=True)
        handle, name = tempfile.mkstemp(prefix=".tokens-", dir=self._path.parent)  # created mode 600
        with os.fdopen(handle, "w") as file:
            json.dump({n: r.model_dump(mode="json") for n, r in records.items()}, file)
        Path(name).replace(self._path)

    def add(self, record: TokenRecord) -> None:
        with self._lock:
            records = self._read()
            if record.name in records:
                raise ArgumentError(f"a token named {record.name!r} exists already; revoke it or choose another name")
            records[record.name] = record
            self._write(records)

    def by_hash(self, digest: str) -> TokenRecord | None:
        with self._lock:
            return {r.hash: r for r in self._read().values()}.get(digest)

    def all(self) -> list[TokenRecord]:
        with self._lock:
            return sorted(self._read().values(), key=lambda r: r.name)

    def revoke(self, name: str) -> bool:
        with self._lock:
            records = self._read()
            if records.pop(name, None) is None:
                return False
            self._write(records)
            return True


class RedisTokenStore:
    """Tokens of a team in Redis: one record per name and an index by hash (every replica sees them)."""

    def __init__(self, client: redis.Redis) -> None:
        self._redis = client

    def add(self, record: TokenRecord) -> None:
        with reachable("the token store"):
            if not self._redis.set(_KEY + record.name, record.model_dump_json(), nx=True):
                raise ArgumentError(f"a token named {record.name!r} exists already; revoke it or choose another name")
            self._redis.set(_BY_HASH + record.hash, record.name)

    def by_hash(self, digest: str) -> TokenRecord | None:
        with reachable("the token store"):
            name = self._redis.get(_BY_HASH + digest)
            raw = self._redis.get(_KEY + name.decode()) if isinstance(name, bytes) else None
        return TokenRecord.model_validate_json(raw) if isinstance(raw, bytes) else None

    def all(self) -> list[TokenRecord]:
        with reachable("the token store"):
            keys = sorted(self._redis.scan_iter(match=_KEY + "*"))
            raws = self._redis.mget(keys) if keys else []
        return [TokenRecord.model_validate_json(r) for r in raws if isinstance(r, bytes)]

    def revoke(self, name: str) -> bool:
        with reachable("the token store"):
            raw = self._redis.get(_KEY + name)
            if not isinstance(raw, bytes):
                return False
            record = TokenRecord.model_validate_json(raw)
            self._redis.delete(_KEY + name, _BY_HASH + record.hash)
        return True
