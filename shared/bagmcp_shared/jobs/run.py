"""Running a queued job to its end: record progress, then the result, failure or cancellation, and the bytes
the job fetched from the object store (counted around it: the worker's threads that read for it add to the
same tally, see fetch_tally.py)."""

from __future__ import annotations

import logging

from bagmcp_shared.errors import BagmcpError, JobCancelledError, sentence
from bagmcp_shared.fetch_tally import tallied
from bagmcp_shared.jobs.kinds import JobRegistry
from bagmcp_shared.jobs.models import Job, JobState
from bagmcp_shared.jobs.progress import ProgressReporter
from bagmcp_shared.jobs.store import JobStore, update

log = logging.getLogger(__name__)


def run_job(registry: JobRegistry, store: JobStore, job_id: str) -> JobState | None:
    """Run a queued (or redelivered) job; returns its final state (None when it no longer exists).
    Safe to run twice: an ended job is left as it is."""
    job = store.get(job_id)
    if job is None:
        return None
    if job.ended:
        return job.state
    if job.cancel_requested:
        return update(store, job_id, state="cancelled", message="cancelled before it started").state
    update(store, job_id, state="running", message="started")
    with tallied() as tally:
        ending = _run(registry, store, job)
    return update(store, job_id, fetched_bytes=tally.fetched_bytes, **ending).state


def _run(registry: JobRegistry, store: JobStore, job: Job) -> dict[str, object]:
    """The job's work; the changes that end it (result, failure or cancellation)."""
    try:
        result = registry.run(job.kind, job.params, ProgressReporter(store, job.id))
    except JobCancelledError:
        return {"state": "cancelled", "message": "cancelled"}
    except BagmcpError as err:
        return {"state": "failed", "error": sentence(err), "message": "failed"}
    except Exception as err:
        log.exception("job %s crashed", job.id)
        return {"state": "failed", "error": f"internal error ({type(err).__name__})", "message": "failed"}
    return {"state": "succeeded", "progress": 1.0, "message": "done", "result": result}
