"""Per-token rate limits shared through Redis: two gateway replicas together admit what one bucket allows
(never more; leases in other replicas may refuse a call early by at most what they hold), and a replica
far from the limit asks Redis once per lease, not once per call."""

from __future__ import annotations

import time
import uuid
from typing import Any

import pytest
import redis

from bagmcp_gateway.access.ratelimit import LEASE_FRACTION, MAX_LEASE, Limit, RedisRateLimiter
from tests.fixtures.mcp_client import http_client
from tests.fixtures.servers import free_port
from tests.integration.stack import Stack, new_token, run_gateway

pytestmark = pytest.mark.anyio
RATE_PER_S = 0.05  # slow refill: the bucket's burst is what two replicas can admit while the test runs
BURST = 12


def _lua_calls(client: redis.Redis) -> int:
    """EVALSHA calls the server ran: the limiter's script (registered, so called by its SHA). Plain EVAL is left
    out: the session's stack shares this Redis and its catalog's scripts run meanwhile (one of them once made a
    lease count 5 where the limiter had made 4)."""
    stats: dict[str, Any] = client.info("commandstats")
    return int(stats.get("cmdstat_evalsha", {}).get("calls", 0))


async def test_two_replicas_together_admit_one_bucket_of_calls(stack: Stack) -> None:
    limits = {"BAGMCP_RATE_LIMIT_PER_S": str(RATE_PER_S), "BAGMCP_RATE_BURST": str(BURST)}
    ports = [free_port(), free_port()]
    with (
        run_gateway(stack, "gateway-shared-1", ports[0], limits),
        run_gateway(stack, "gateway-shared-2", ports[1], limits),
    ):
        token = new_token(stack, "two-replica-caller")
        urls = [f"http://127.0.0.1:{port}/mcp" for port in ports]
        admitted = dict.fromkeys(urls, 0)
        began = time.monotonic()
        async with http_client(urls[0], token) as first, http_client(urls[1], token) as second:
            for turn in range(3 * BURST):
                url, client = (urls[0], first) if turn % 2 == 0 else (urls[1], second)
                answer = await client.call_tool("list_bags", {"limit": 1})
                if answer.is_error:
                    assert answer.structured_content is not None
                    assert answer.structured_content["retryAfterSeconds"] > 0
                    break
                admitted[url] += 1
        refilled = int(RATE_PER_S * (time.monotonic() - began)) + 1
        assert BURST <= sum(admitted.values()) <= BURST + refilled, admitted
        assert all(count >= BURST // 2 - 1 for count in admitted.values()), admitted  # both served from one bucket


async def test_far_from_the_limit_a_replica_asks_redis_once_per_lease(redis_url: str) -> None:
    client = redis.Redis.from_url(redis_url)
    limiter = RedisRateLimiter(client, Limit(rate_per_s=1.0, burst=1000))
    who = f"lease-{uuid.uuid4().hex[:8]}"
    await limiter.take(f"{who}-warm")  # loads the script into a fresh Redis (a refused EVALSHA, then one)
    before = _lua_calls(client)
    waits = [await limiter.take(who) for _ in range(4 * MAX_LEASE)]
    assert waits == [0.0] * (4 * MAX_LEASE)
    assert _lua_calls(client) - before == 4  # a full lease each time (a quarter of 1000 is more than MAX_LEASE)
    assert 1000 * LEASE_FRACTION > MAX_LEASE
    left = float(client.hget(f"bagmcp:rate:{who}", "tokens") or 0)
    assert 1000 - 4 * MAX_LEASE <= left <= 1000 - 4 * MAX_LEASE + 1  # what was leased left the bucket


async def test_near_the_limit_every_call_is_decided_by_redis_and_the_bucket_is_exact(redis_url: str) -> None:
    client = redis.Redis.from_url(redis_url)
    limiter = RedisRateLimiter(client, Limit(rate_per_s=0.01, burst=3))
    who = f"exact-{uuid.uuid4().hex[:8]}"
    await limiter.take(f"{who}-warm")  # loads the script into a fresh Redis (a refused EVALSHA, then one)
    before = _lua_calls(client)
    waits = [await limiter.take(who) for _ in range(4)]
    assert waits[:3] == [0.0, 0.0, 0.0]
    assert waits[3] > 0
    assert _lua_calls(client) - before == 4
