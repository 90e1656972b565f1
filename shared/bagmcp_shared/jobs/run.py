"""Running a queued job to its end: record progress, then the result, failure or cancellation."""

from __future__ import annotations

import logging

from bagmcp_shared.errors import BagmcpError, JobCancelledError, sentence
from bagmcp_shared.jobs.kinds import JobRegistry
from bagmcp_shared.jobs.models import JobState
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
    try:
        result = registry.run(job.kind, job.params, ProgressReporter(store, job_id))
    except JobCancelledError:
        return update(store, job_id, state="cancelled", message="cancelled").state
    except BagmcpError as err:
        return update(store, job_id, state="failed", error=sentence(err), message="failed").state
    except Exception as err:
        log.exception("job %s crashed", job_id)
        return update(
            store, job_id, state="failed", error=f"internal error ({type(err).__name__})", message="failed"
        ).state
    return update(store, job_id, state="succeeded", progress=1.0, message="done", result=result).state
