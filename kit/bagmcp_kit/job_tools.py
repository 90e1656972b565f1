"""``get_job`` and ``cancel_job``: one pair of tools for the jobs of every service (listed once, over the shared
job store), declared like every other tool; a caller sees and cancels only its own jobs (``who`` is set from
the request, never an argument)."""

from __future__ import annotations

from typing import Annotated

from mcp.server.mcpserver import Context, MCPServer
from pydantic import BaseModel, Field

from bagmcp_kit.arguments import STOPS, register
from bagmcp_kit.declared import GIVEN, Declared, short_specs
from bagmcp_kit.fetch_meta import fetched_bytes_meta
from bagmcp_kit.identity import LOCAL_CALLER, caller
from bagmcp_kit.job_info import JobInfo
from bagmcp_shared.fetch_tally import count_fetched
from bagmcp_shared.jobs import JobStore, Progress, owned


class JobParams(BaseModel):
    job_id: Annotated[str, Field(description="job_id from a tool's answer")]
    who: Annotated[str, GIVEN] = LOCAL_CALLER


def _who(ctx: Context, jobs: JobStore) -> dict[str, str]:
    return {"who": caller(ctx)}


def get_job(jobs: JobStore, params: JobParams, progress: Progress) -> JobInfo:
    """The job; an ended one's answer names in ``_meta`` the bytes it fetched (each time it is asked for)."""
    job = owned(jobs, params.job_id, params.who)
    count_fetched(job.fetched_bytes)
    return JobInfo.of(job)


def cancel_job(jobs: JobStore, params: JobParams, progress: Progress) -> JobInfo:
    job = owned(jobs, params.job_id, params.who)
    if job.ended:
        return JobInfo.of(job)
    jobs.request_cancel(params.job_id)
    return get_job(jobs, params, progress).model_copy(update={"message": "cancellation requested"})


GET_JOB = Declared[JobStore, JobParams, JobInfo](
    "get_job",
    'State, progress and, when done, the result of a long call\'s job. Example: get_job(job_id="3f2a...").',
    JobParams,
    JobInfo,
    get_job,
    lambda j: f"job {j.job_id}: {j.state} ({j.progress:.0%}) {j.message}",
    long=False,
    given=_who,
)
CANCEL_JOB = Declared[JobStore, JobParams, JobInfo](
    "cancel_job",
    'Stop a queued or running job; nothing is left half-done. Example: cancel_job(job_id="3f2a...").',
    JobParams,
    JobInfo,
    cancel_job,
    lambda j: f"job {j.job_id}: {j.state}; {j.message}",
    annotations=STOPS,
    long=False,
    given=_who,
)


def build_jobs_server(jobs: JobStore) -> MCPServer:
    """The jobs MCP server; the gateway (or the embedded command) hosts it next to the services."""
    server = MCPServer("bagmcp-jobs", instructions="Follow and stop the long work other tools started.")
    register(server, short_specs(jobs, (GET_JOB, CANCEL_JOB)))
    server.middleware.append(fetched_bytes_meta)
    return server
