"""Per-token rate limits: a token bucket (``rate_per_s`` refill, ``burst`` capacity) kept in memory
(one process) or in Redis (every gateway replica shares it).

With Redis, a replica does not ask Redis on every call: it takes a *lease* of several calls at once when
the bucket is far from empty (a quarter of what it holds, at most ``MAX_LEASE``) and serves them from
memory; near empty the leases shrink to one call, so the limit is exact where it matters. Leased calls
left unused after ``LEASE_S`` go back to the bucket with the next lease. Tolerance: the replicas together
never admit more than the bucket allows (each admitted call took a token out of Redis); a call can be
refused early by at most the calls other replicas hold in their leases at that moment (below a quarter of
the bucket each, and at most ``MAX_LEASE``).
"""

from __future__ import annotations

import logging
import math
import time
from dataclasses import dataclass
from typing import Protocol

import anyio
import redis

from bagmcp_shared.errors import StorageError
from bagmcp_shared.redis_errors import reachable

log = logging.getLogger(__name__)

MAX_LEASE = 8
LEASE_FRACTION = 0.25
LEASE_S = 1.0

# KEYS[1] the bucket; ARGV rate, burst, calls given back, lease fraction, max lease.
# Returns {calls granted (0 when refused), seconds to wait (string)}.
_BUCKET = """
local now_parts = redis.call('TIME')
local now = tonumber(now_parts[1]) + tonumber(now_parts[2]) / 1000000
local rate, burst = tonumber(ARGV[1]), tonumber(ARGV[2])
local state = redis.call('HMGET', KEYS[1], 'tokens', 'ts')
local tokens = tonumber(state[1]) or burst
local ts = tonumber(state[2]) or now
tokens = math.min(burst, tokens + math.max(0, now - ts) * rate + tonumber(ARGV[3]))
local granted = 0
local wait = 0
if tokens >= 1 then
  granted = math.max(1, math.min(tonumber(ARGV[5]), math.floor(tokens * tonumber(ARGV[4]))))
  tokens = tokens - granted
else
  wait = (1 - tokens) / rate
end
redis.call('HSET', KEYS[1], 'tokens', tostring(tokens), 'ts', tostring(now))
redis.call('EXPIRE', KEYS[1], math.ceil(burst / rate) + 1)
return {granted, tostring(wait)}
"""


@dataclass(frozen=True)
class Limit:
    rate_per_s: float
    burst: int


class RateLimiter(Protocol):
    async def take(self, who: str) -> float:
        """0 when ``who`` may make a call now, else the seconds to wait before the next one."""
        ...


class MemoryRateLimiter:
    def __init__(self, limit: Limit) -> None:
        self._limit = limit
        self._buckets: dict[str, tuple[float, float]] = {}

    async def take(self, who: str) -> float:
        """On the event loop only (no await inside), so no lock is needed."""
        now = time.monotonic()
        tokens, last = self._buckets.get(who, (float(self._limit.burst), now))
        tokens = min(float(self._limit.burst), tokens + (now - last) * self._limit.rate_per_s)
        if tokens >= 1:
            self._buckets[who] = (tokens - 1, now)
            return 0.0
        self._buckets[who] = (tokens, now)
        return (1 - tokens) / self._limit.rate_per_s


@dataclass
class _Lease:
    calls: int
    since: float


class RedisRateLimiter:
    def __init__(self, client: redis.Redis, limit: Limit) -> None:
        self._limit = limit
        self._script = client.register_script(_BUCKET)
        self._leases: dict[str, _Lease] = {}

    def _lease(self, who: str, returned: int) -> tuple[int, float]:
        with reachable("the rate limiter"):
            granted, wait = self._script(
                keys=[f"bagmcp:rate:{who}"],
                args=[self._limit.rate_per_s, self._limit.burst, returned, LEASE_FRACTION, MAX_LEASE],
            )
        return int(granted), max(float(wait), 0.001)

    async def take(self, who: str) -> float:
        now = time.monotonic()
        lease = self._leases.get(who)
        if lease is not None and lease.calls > 0 and now - lease.since < LEASE_S:
            lease.calls -= 1
            return 0.0
        returned = self._leases.pop(who).calls if lease is not None else 0
        try:
            granted, wait = await anyio.to_thread.run_sync(self._lease, who, returned)
        except StorageError as err:  # fails open: while Redis is unreachable the services say what is down
            log.warning("not limiting calls: %s", err)
            return 0.0
        if not granted:
            return wait
        if granted > 1:  # a call that leased meanwhile keeps its own lease: the two are merged
            held = self._leases.setdefault(who, _Lease(0, now))
            held.calls += granted - 1
        return 0.0


def retry_after_s(wait_s: float) -> float:
    """Seconds to tell a caller, rounded up to 10 ms."""
    return math.ceil(wait_s * 100) / 100
