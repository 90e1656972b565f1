"""Job records: updates never undo an end or a cancel; waiting wakes on a change, not on a poll."""

from __future__ import annotations

import threading
import time

import pytest

from bagmcp_shared.errors import JobCancelledError
from bagmcp_shared.jobs import Job, MemoryJobStore, ProgressReporter, update


def test_a_finished_job_is_never_changed_and_a_cancel_survives_progress_updates() -> None:
    store = MemoryJobStore()
    job = Job.new("search", "alice", {})
    store.put(job)
    update(store, job.id, state="running")
    store.request_cancel(job.id)
    update(store, job.id, progress=0.5, message="halfway")
    reporter = ProgressReporter(store, job.id, every_s=0)
    with pytest.raises(JobCancelledError):
        reporter(0.6, "more")
    update(store, job.id, state="succeeded", result={"n": 1})
    assert update(store, job.id, state="running", progress=0.1).state == "succeeded"
    assert store.get(job.id).result == {"n": 1}  # type: ignore[union-attr]


def test_a_waiter_wakes_when_its_job_ends_not_at_its_timeout() -> None:
    store = MemoryJobStore()
    job = Job.new("search", "alice", {})
    store.put(job)

    def finish() -> None:
        time.sleep(0.05)
        update(store, job.id, state="succeeded", result={"n": 1})

    threading.Thread(target=finish).start()
    began = time.monotonic()
    seen = store.wait(job.id, newer_than=job.updated_at, timeout_s=30)
    assert seen is not None
    assert seen.state == "succeeded"
    assert time.monotonic() - began < 5  # woken by the change, long before the 30 s timeout


def test_shutting_down_asks_unfinished_jobs_to_stop_and_leaves_ended_ones_alone() -> None:
    store = MemoryJobStore()
    running, done = Job.new("filter", "bob", {}), Job.new("filter", "bob", {})
    store.put(running)
    store.put(done)
    update(store, done.id, state="succeeded")
    store.cancel_unfinished()
    assert store.get(done.id).cancel_requested is False  # type: ignore[union-attr]
    with pytest.raises(JobCancelledError):
        ProgressReporter(store, running.id, every_s=0)(0.5, "still working")
