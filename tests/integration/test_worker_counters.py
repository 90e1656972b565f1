"""Workers' counters summed in a real Redis: each flush adds what its process counted since the last one that
reached Redis, two processes' flushes add up, and a Redis that is down fails neither a flush nor a read; the
counts of a failed flush arrive with the next one. A service's /metrics text names each process's counters."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest

from bagmcp_kit.service_app import exposition_text
from bagmcp_shared.access.blocks import BlockCounters
from bagmcp_shared.redis_connection import redis_client
from bagmcp_shared.worker_counters import CounterFlush, WorkerSums
from tests.fixtures.faults import redis_server
from tests.fixtures.restartable import Restartable
from tests.fixtures.servers import free_port

HITS, MISSES, FETCHED = (
    "bagmcp_block_cache_hits_total",
    "bagmcp_block_cache_misses_total",
    "bagmcp_s3_fetched_bytes_total",
)


@pytest.fixture
def redis(tmp_path: Path) -> Iterator[tuple[Restartable, WorkerSums]]:
    """A Redis of the test's own (to stop and start) and the sums of the queue "analysis" in it."""
    port = free_port()
    server = redis_server(tmp_path, port)
    server.start()
    try:
        yield server, WorkerSums(redis_client(f"redis://127.0.0.1:{port}/0"), "analysis")
    finally:
        server.stop(timeout_s=5)


def test_flushes_of_two_processes_add_up_and_an_unchanged_process_adds_nothing(
    redis: tuple[Restartable, WorkerSums],
) -> None:
    _, sums = redis
    one, two = BlockCounters(), BlockCounters()
    first, second = CounterFlush(sums, one.snapshot), CounterFlush(sums, two.snapshot)
    one.add(hits=3, misses=2, fetched_bytes=2_097_152)
    first.flush()
    one.add(hits=1)
    first.flush()
    first.flush()  # nothing new: the sums stay
    two.add(misses=1, fetched_bytes=1_048_576, whole_bytes=512)
    second.flush()
    assert sums.read() == {
        HITS: 4,
        MISSES: 3,
        FETCHED: 3_145_728,
        "bagmcp_s3_whole_object_bytes_total": 512,
    }


def test_a_flush_while_redis_is_down_keeps_its_counts_for_the_next_and_reads_say_unavailable(
    redis: tuple[Restartable, WorkerSums],
) -> None:
    server, sums = redis
    counters = BlockCounters()
    flush = CounterFlush(sums, counters.snapshot)
    counters.add(misses=1, fetched_bytes=1000)
    flush.flush()
    server.stop(timeout_s=5)
    counters.add(misses=2, fetched_bytes=500)
    flush.flush()  # no exception: the task it ends is unharmed
    assert sums.read() is None
    server.start()
    counters.add(hits=1)
    flush.flush()
    assert sums.read() == {MISSES: 3, FETCHED: 1500, HITS: 1}


def test_metrics_text_labels_each_process_and_says_when_the_workers_are_unavailable() -> None:
    own = {HITS: 5, FETCHED: 70}
    assert exposition_text({"service": own, "workers": {HITS: 2, FETCHED: 900}}) == (
        f"# TYPE {HITS} counter\n"
        f'{HITS}{{process="service"}} 5\n'
        f'{HITS}{{process="workers"}} 2\n'
        f"# TYPE {FETCHED} counter\n"
        f'{FETCHED}{{process="service"}} 70\n'
        f'{FETCHED}{{process="workers"}} 900\n'
    )
    assert exposition_text({"service": own, "workers": None}) == (
        "# workers counters unavailable now\n"
        f"# TYPE {HITS} counter\n"
        f'{HITS}{{process="service"}} 5\n'
        f"# TYPE {FETCHED} counter\n"
        f'{FETCHED}{{process="service"}} 70\n'
    )
