"""Per-token rate limits: a token bucket (``rate_per_s`` refill, ``burst`` capacity) kept in memory
(one process) or in Redis (every gateway replica shares it)."""

from __future__ import annotations

import logging
import math
import threading
import time
from dataclasses import dataclass
from typing import Protocol

import redis

from bagmcp_shared.errors import StorageError
from bagmcp_shared.redis_errors import reachable

log = logging.getLogger(__name__)

# KEYS[1] the bucket; ARGV rate, burst. Returns {allowed (1/0), seconds to wait (string)}.
_BUCKET = """
local now_parts = redis.call('TIME')
local now = tonumber(now_parts[1]) + tonumber(now_parts[2]) / 1000000
local rate, burst = tonumber(ARGV[1]), tonumber(ARGV[2])
local state = redis.call('HMGET', KEYS[1], 'tokens', 'ts')
local tokens = tonumber(state[1]) or burst
local ts = tonumber(state[2]) or now
tokens = math.min(burst, tokens + math.max(0, now - ts) * rate)
local allowed = 0
local wait = 0
if tokens >= 1 then
  tokens = tokens - 1
  allowed = 1
else
  wait = (1 - tokens) / rate
end
redis.call('HSET', KEYS[1], 'tokens', tostring(tokens), 'ts', tostring(now))
redis.call('EXPIRE', KEYS[1], math.ceil(burst / rate) + 1)
return {allowed, tostring(wait)}
"""


@dataclass(frozen=True)
class Limit:
    rate_per_s: float
    burst: int


class RateLimiter(Protocol):
    def take(self, who: str) -> float:
        """0 when ``who`` may make a call now, else the seconds to wait before the next one."""
        ...


class MemoryRateLimiter:
    def __init__(self, limit: Limit) -> None:
        self._limit = limit
        self._buckets: dict[str, tuple[float, float]] = {}
        self._lock = threading.Lock()

    def take(self, who: str) -> float:
        now = time.monotonic()
        with self._lock:
            tokens, last = self._buckets.get(who, (float(self._limit.burst), now))
            tokens = min(float(self._limit.burst), tokens + (now - last) * self._limit.rate_per_s)
            if tokens >= 1:
                self._buckets[who] = (tokens - 1, now)
                return 0.0
            self._buckets[who] = (tokens, now)
            return (1 - tokens) / self._limit.rate_per_s


class RedisRateLimiter:
    def __init__(self, client: redis.Redis, limit: Limit) -> None:
        self._limit = limit
        self._script = client.register_script(_BUCKET)

    def take(self, who: str) -> float:
        """Fails open: while Redis is unreachable calls are not limited (the services say what is down)."""
        try:
            with reachable("the rate limiter"):
                allowed, wait = self._script(
                    keys=[f"bagmcp:rate:{who}"], args=[self._limit.rate_per_s, self._limit.burst]
                )
        except StorageError as err:
            log.warning("not limiting calls: %s", err)
            return 0.0
        return 0.0 if int(allowed) else max(float(wait), 0.001)


def retry_after_s(wait_s: float) -> float:
    """Seconds to tell a caller, rounded up to 10 ms."""
    return math.ceil(wait_s * 100) / 100
