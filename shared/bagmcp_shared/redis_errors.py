"""Redis failures as the project's storage error, naming what was unreachable."""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager

import redis

from bagmcp_shared.errors import StorageError


@contextmanager
def reachable(what: str) -> Iterator[None]:
    """Run a Redis call; a connection or server failure becomes StorageError("<what> (Redis) is unreachable")."""
    try:
        yield
    except redis.RedisError as err:
        raise StorageError(f"{what} (Redis) is unreachable: {err}") from err


def responds_to_ping(client: redis.Redis) -> bool:
    """Redis answers a PING (for readiness checks)."""
    try:
        return bool(client.ping())
    except redis.RedisError:
        return False
