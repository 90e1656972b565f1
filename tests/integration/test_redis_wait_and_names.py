"""The team stores in a real Redis: a waiter for a job is woken by the job's change (no polling), and a
bag named exactly is found through its name reservation and forgotten when deleted."""

from __future__ import annotations

import threading
import time

import pytest
import redis

from bagmcp_shared.catalog import RedisCatalog, resolve_bag
from bagmcp_shared.errors import BagNotFoundError
from bagmcp_shared.jobs import Job, RedisJobStore, update
from tests.fixtures.records import stored_record


class CountingJobStore(RedisJobStore):
    """Counts the reads of a job: a polling wait would read it again and again until the job ends."""

    def __init__(self, client: redis.Redis) -> None:
        super().__init__(client)
        self.reads = 0

    def get(self, job_id: str) -> Job | None:
        self.reads += 1
        return super().get(job_id)


def test_a_waiter_is_woken_by_the_finished_job_not_by_polling(redis_url: str) -> None:
    client = redis.Redis.from_url(redis_url)
    store = CountingJobStore(client)
    job = Job.new("search", "alice", {})
    store.put(job)
    started = threading.Event()

    def finish() -> None:
        started.wait()
        time.sleep(3.0)  # the waiter sits idle meanwhile: a poll of once a second or faster would read 3+ times
        update(RedisJobStore(client), job.id, state="succeeded", result={"n": 1})

    threading.Thread(target=finish).start()
    started.set()
    began = time.monotonic()
    seen = store.wait(job.id, newer_than=job.updated_at, timeout_s=30)
    assert time.monotonic() - began >= 2.9  # woken by the end of the job, not earlier
    assert seen is not None
    assert seen.state == "succeeded"
    assert seen.result == {"n": 1}
    assert store.reads <= 3  # once on subscribing, once per notification: no reads while nothing changed


def test_a_bag_named_exactly_is_found_by_its_name_and_forgotten_once_deleted(redis_url: str) -> None:
    catalog = RedisCatalog(redis.Redis.from_url(redis_url))
    catalog.claim_name("named-run", "abc123")
    assert catalog.add(stored_record("abc123", "named-run"))
    found = catalog.named("named-run")
    assert found is not None
    assert found.id == "abc123"
    assert resolve_bag(catalog, "named-run").id == "abc123"
    catalog.delete("abc123")
    assert catalog.named("named-run") is None
    with pytest.raises(BagNotFoundError):
        resolve_bag(catalog, "named-run")
    catalog.claim_name("named-run", "def456")  # the same name, another upload
    assert catalog.add(stored_record("def456", "named-run"))
    assert resolve_bag(catalog, "named-run").id == "def456"
