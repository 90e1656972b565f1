"""``get_job`` and ``cancel_job``: one pair of tools for the jobs of every service (listed once,
over the shared job store); a caller sees and cancels only its own jobs."""

from __future__ import annotations

from typing import Annotated

from mcp.server.mcpserver import Context, MCPServer
from mcp.types import CallToolResult
from pydantic import Field

from bagmcp_kit.answers import run_query
from bagmcp_kit.arguments import READ_ONLY, STOPS, register
from bagmcp_kit.identity import caller
from bagmcp_kit.jobs import JobInfo
from bagmcp_kit.toolsets import tool, tools_of
from bagmcp_shared.jobs import JobStore, owned

JobId = Annotated[str, Field(description="job_id from a tool's answer")]


class JobTools:
    def __init__(self, jobs: JobStore) -> None:
        self._jobs = jobs

    @tool(READ_ONLY)
    def get_job(self, ctx: Context, job_id: JobId) -> Annotated[CallToolResult, JobInfo]:
        """State, progress and, when done, the result of a long call's job.
        Example: get_job(job_id="3f2a...")."""
        who = caller(ctx)
        return run_query(
            lambda: JobInfo.of(owned(self._jobs, job_id, who)),
            lambda j: f"job {j.job_id}: {j.state} ({j.progress:.0%}) {j.message}",
        )

    @tool(STOPS)
    def cancel_job(self, ctx: Context, job_id: JobId) -> Annotated[CallToolResult, JobInfo]:
        """Stop a queued or running job; nothing is left half-done. Example: cancel_job(job_id="3f2a...")."""
        who = caller(ctx)
        return run_query(lambda: self._cancel(job_id, who), lambda j: f"job {j.job_id}: {j.state}; {j.message}")

    def _cancel(self, job_id: str, who: str) -> JobInfo:
        job = owned(self._jobs, job_id, who)
        if job.ended:
            return JobInfo.of(job)
        self._jobs.request_cancel(job_id)
        return JobInfo.of(owned(self._jobs, job_id, who)).model_copy(update={"message": "cancellation requested"})


def build_jobs_server(jobs: JobStore) -> MCPServer:
    """The jobs MCP server; the gateway (or the embedded command) hosts it next to the services."""
    server = MCPServer("bagmcp-jobs", instructions="Follow and stop the long work other tools started.")
    register(server, tools_of(JobTools(jobs)))
    return server
