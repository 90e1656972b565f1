"""Change events (``tools/list_changed``) shared by every gateway replica through Redis pub/sub.

The SDK's ``SubscriptionBus`` seam: ``publish`` sends the event to one Redis channel; ``run`` receives
what any replica published (this one included) and hands it to this replica's listeners, which are
its clients' ``subscriptions/listen`` streams and its own tool catalog (so a replica re-lists its
upstreams as soon as another noticed a change). Without Redis a replica tells only its own clients.
"""

from __future__ import annotations

import hashlib
import json
import logging
from collections.abc import Callable, Sequence

import anyio
import redis
import redis.asyncio
from anyio.abc import TaskStatus
from mcp.server.subscriptions import InMemorySubscriptionBus, ServerEvent
from mcp.shared.subscriptions import event_from_wire, event_to_notification

from bagmcp_gateway.upstreams.upstream import Upstream

log = logging.getLogger(__name__)
CHANNEL = "bagmcp:gateway:events:"


def channel_for(upstreams: Sequence[Upstream]) -> str:
    """One channel per upstream configuration: the replicas of one gateway share it, other gateways on the
    same Redis (another team's, a test's) never hear its events."""
    described = ",".join(f"{u.name}={u.url or 'in-process'}@{u.prefix or ''}" for u in upstreams)
    return CHANNEL + hashlib.sha256(described.encode()).hexdigest()[:16]


def encode(event: ServerEvent) -> str:
    return event_to_notification(event, {}).model_dump_json(by_alias=True, exclude_none=True)


def decode(body: bytes | str) -> ServerEvent | None:
    try:
        raw = json.loads(body)
        return event_from_wire(str(raw["method"]), raw.get("params"))
    except (ValueError, KeyError, TypeError):
        return None


class RedisSubscriptionBus:
    def __init__(self, url: str, *, channel: str, retry_s: float = 1.0) -> None:
        self._redis = redis.asyncio.Redis.from_url(url)
        self._channel = channel
        self._retry_s = retry_s
        self._local = InMemorySubscriptionBus()

    async def publish(self, event: ServerEvent) -> None:
        try:
            await self._redis.publish(self._channel, encode(event))
        except redis.RedisError as err:  # Redis away: this replica's clients are still told
            log.warning("change event not shared with the other replicas (%s); telling this replica's clients", err)
            await self._local.publish(event)

    def subscribe(self, listener: Callable[[ServerEvent], None]) -> Callable[[], None]:
        return self._local.subscribe(listener)

    async def run(self, *, task_status: TaskStatus[None] = anyio.TASK_STATUS_IGNORED) -> None:
        """Receive the channel until cancelled (reconnecting when Redis goes away)."""
        started = False
        try:
            while True:
                try:
                    async with self._redis.pubsub() as pubsub:
                        await pubsub.subscribe(self._channel)
                        if not started:
                            started = True
                            task_status.started()
                        async for message in pubsub.listen():
                            event = decode(message["data"]) if message.get("type") == "message" else None
                            if event is not None:
                                await self._local.publish(event)
                except redis.RedisError as err:
                    log.warning("change events from other replicas paused: %s", err)
                if not started:
                    started = True
                    task_status.started()
                await anyio.sleep(self._retry_s)
        finally:
            with anyio.CancelScope(shield=True):
                await self._redis.aclose()
