"""Each tool call's answer says how many bytes its service fetched from the object store for it, in
``_meta["bagmcp/fetchedBytes"]`` (absent when nothing was fetched); the gateway puts the figure on the call's
audit line. Work a worker ran as a job fetched in the worker: the job records those bytes when it ends
(jobs/run.py), and they are added to the tally of the call that hands its result back, the long call that
waited for it (longwork.py) or ``get_job`` (job_tools.py)."""

from __future__ import annotations

from typing import Any

from mcp.server.context import CallNext, HandlerResult, ServerRequestContext
from mcp.types import CallToolResult

from bagmcp_shared.fetch_tally import tallied

FETCHED_META_KEY = "bagmcp/fetchedBytes"


async def fetched_bytes_meta(ctx: ServerRequestContext[Any, Any], call_next: CallNext) -> HandlerResult:
    """Server middleware: count what a tools/call fetched and name it on the result."""
    if ctx.method != "tools/call":
        return await call_next(ctx)
    with tallied() as tally:
        result = await call_next(ctx)
    if tally.fetched_bytes:
        if isinstance(result, CallToolResult):
            result.meta = {**(result.meta or {}), FETCHED_META_KEY: tally.fetched_bytes}
        elif isinstance(result, dict):
            result["_meta"] = {**(result.get("_meta") or {}), FETCHED_META_KEY: tally.fetched_bytes}
    return result
