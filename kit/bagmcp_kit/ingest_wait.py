"""A call about a bag still being ingested waits for the ingest, within the service's time budget, sending the
ingest's progress, then answers; only past the budget does it say how far the ingest is and when to ask again.

Right after `bagmcp serve` starts (and over stdio, the Claude Desktop mode) the first call an agent makes is
usually about a bag still being ingested; answering "try again in a few seconds" made agents give up. The
wait is a middleware over every tool of a service, so no tool has to remember it: it reads the ``bag`` (or
``bags``) argument, looks the bag up in the catalog (one catalog read per poll, 0.2 s apart), and lets
unknown names through for the tool to answer with its own error.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import anyio
from mcp.server.context import CallNext, HandlerResult, ServerRequestContext
from mcp.types import CallToolResult, TextContent

from bagmcp_shared.catalog import BagRecord, Catalog, resolve_bag
from bagmcp_shared.errors import BagmcpError

POLL_S = 0.2


def bag_refs(params: object) -> list[str]:
    """The bags a tools/call names: its ``bag`` argument and the items of its ``bags`` argument."""
    arguments = params.get("arguments") if isinstance(params, dict) else None
    if not isinstance(arguments, dict):
        return []
    refs = [arguments.get("bag")]
    if isinstance(many := arguments.get("bags"), list):
        refs.extend(many)
    return [r for r in refs if isinstance(r, str) and r.strip()]


def _record(catalog: Catalog, ref: str) -> BagRecord | None:
    try:
        return resolve_bag(catalog, ref)
    except BagmcpError:
        return None  # unknown or ambiguous: the tool says so in its own words


@dataclass
class _Watch:
    """How far one bag's ingest went while the call waited, to say when it may be done."""

    first_progress: float
    waited_s: float = 0.0

    def eta_s(self, progress: float) -> float | None:
        gained = progress - self.first_progress
        return (1.0 - progress) * self.waited_s / gained if gained > 0 and self.waited_s > 0 else None


def _still_ingesting(record: BagRecord, watch: _Watch) -> CallToolResult:
    progress = record.progress or 0.0
    eta = watch.eta_s(progress)
    when = f"ask again in about {max(eta, 1.0):.0f} s" if eta is not None else "ask again in a few seconds"
    text = (
        f"bag {record.name} is still being ingested ({progress:.0%} done after waiting {watch.waited_s:.0f} s); "
        f"{when} (list_bags shows its progress)"
    )
    return CallToolResult(content=[TextContent(type="text", text=text)], is_error=True)


@dataclass(frozen=True)
class IngestWait:
    """What a service's calls wait for: bags of this catalog, at most the service's time budget."""

    catalog: Catalog
    budget_s: float


def wait_for_ingest(catalog: Catalog, *, budget_s: float) -> Any:
    """Middleware: hold tools/call until the bags it names are ingested, at most ``budget_s``."""

    async def wait(ctx: ServerRequestContext[Any, Any], call_next: CallNext) -> HandlerResult:
        refs = bag_refs(ctx.params) if ctx.method == "tools/call" else []
        if refs:
            late = await _wait_all(ctx, catalog, refs, deadline=time.monotonic() + budget_s)
            if late is not None:
                return late
        return await call_next(ctx)

    return wait


async def _wait_all(
    ctx: ServerRequestContext[Any, Any], catalog: Catalog, refs: Sequence[str], *, deadline: float
) -> CallToolResult | None:
    started = time.monotonic()
    for ref in refs:
        record = await anyio.to_thread.run_sync(_record, catalog, ref)
        watch = _Watch(record.progress or 0.0) if record is not None else _Watch(0.0)
        while record is not None and record.status == "ingesting":
            watch.waited_s = time.monotonic() - started
            if time.monotonic() >= deadline:
                return _still_ingesting(record, watch)
            await ctx.session.report_progress(record.progress or 0.0, 1.0, f"waiting for {record.name} to be ingested")
            await anyio.sleep(POLL_S)
            record = await anyio.to_thread.run_sync(_record, catalog, ref)
    return None
