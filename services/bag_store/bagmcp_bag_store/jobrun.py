"""Running a job: dispatch by kind, record progress, result, failure or cancellation."""

from __future__ import annotations

import logging
from collections.abc import Callable

from pydantic import JsonValue

from bagmcp_bag_store.deps import BagStoreDeps
from bagmcp_bag_store.jobs import TERMINAL, JobCancelledError, ProgressReporter, update
from bagmcp_bag_store.search import search_messages
from bagmcp_shared.bags.writer import FilterCancelled
from bagmcp_shared.errors import BagmcpError

log = logging.getLogger(__name__)
Work = Callable[[BagStoreDeps, dict[str, JsonValue], ProgressReporter], dict[str, JsonValue]]


def _search(deps: BagStoreDeps, params: dict[str, JsonValue], report: ProgressReporter) -> dict[str, JsonValue]:
    return search_messages(deps, params, report).model_dump(mode="json")


def _filter(deps: BagStoreDeps, params: dict[str, JsonValue], report: ProgressReporter) -> dict[str, JsonValue]:
    from bagmcp_bag_store.filtering import filter_bag

    return filter_bag(deps, params, report).model_dump(mode="json")


KINDS: dict[str, Work] = {"search": _search, "filter": _filter}


def run_job(deps: BagStoreDeps, job_id: str) -> str:
    """Run a queued (or redelivered) job to its end; returns the final state. Idempotent on ended jobs."""
    job = deps.jobs.get(job_id)
    if job is None:
        return "missing"
    if job.state in TERMINAL:
        return job.state
    if job.cancel_requested:
        update(deps.jobs, job_id, state="cancelled", message="cancelled before it started")
        return "cancelled"
    update(deps.jobs, job_id, state="running", message="started")
    report = ProgressReporter(deps.jobs, job_id)
    try:
        result = KINDS[job.kind](deps, job.params, report)
    except (JobCancelledError, FilterCancelled):
        update(deps.jobs, job_id, state="cancelled", message="cancelled")
        return "cancelled"
    except BagmcpError as err:
        update(deps.jobs, job_id, state="failed", error=str(err), message="failed")
        return "failed"
    except Exception as err:
        log.exception("job %s crashed", job_id)
        update(
            deps.jobs,
            job_id,
            state="failed",
            error=f"internal error ({type(err).__name__})",
            message="failed",
        )
        return "failed"
    update(deps.jobs, job_id, state="succeeded", progress=1.0, message="done", result=result)
    return "succeeded"
