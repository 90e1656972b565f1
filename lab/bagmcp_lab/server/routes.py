"""The Lab's REST routes under /api/v1/lab (read scope; each route a few lines over the modules beside it).

POST chat (a streamed chat turn), POST runs (start a benchmark), GET runs (yours), GET {run_id} (progress
and records), POST {run_id}/cancel, GET {run_id}/results (results.json), GET {run_id}/report (report.md),
GET {run_id}/latency and {run_id}/calls (the figures), GET providers (what the server offers)."""

from __future__ import annotations

from typing import Any, Literal

import anyio
from fastapi import APIRouter, Depends, Request
from fastapi.responses import JSONResponse, Response, StreamingResponse
from pydantic import Field

from bagmcp_lab.errors import KeyMissingError, LabError, ProviderError, TooManyRunsError
from bagmcp_lab.figures import CALLS_FIGURE, LATENCY_FIGURE, figure_png
from bagmcp_lab.providers import PROVIDERS
from bagmcp_lab.report import TaskRow, model_label, render_report
from bagmcp_lab.runner import BenchmarkPlan
from bagmcp_lab.server.chat import ChatRequest, chat_lines
from bagmcp_lab.server.keys import ModelRequest, choose_model
from bagmcp_lab.server.runs import LabRun, RunNotFoundError
from bagmcp_lab.server.service import Caller, LabService
from bagmcp_shared.errors import BagmcpError

LAB_STATUSES: list[tuple[type[BagmcpError], int, str]] = [
    (TooManyRunsError, 429, "too_many_runs"),
    (RunNotFoundError, 404, "run_not_found"),
    (KeyMissingError, 400, "key_missing"),
    (ProviderError, 502, "provider_failed"),
    (LabError, 400, "lab_error"),
]


class RunRequest(ModelRequest):
    bag: str = Field(min_length=1, max_length=300)
    tasks: Literal["paper", "all"] = "paper"
    repeat: int = Field(default=1, ge=1, le=5)
    max_turns: int = Field(default=10, ge=1, le=30)


def _rows(run: LabRun) -> dict[str, TaskRow]:
    return {t["id"]: TaskRow(t["id"], t["title"], frozenset()) for t in run.tasks}


def build_lab_router(lab: LabService) -> APIRouter:
    router = APIRouter(prefix="/api/v1/lab", tags=["lab"])

    def caller(request: Request) -> Caller:
        return lab.caller(request)

    who_calls = Depends(caller)  # the caller of each route (its token for the MCP calls, its runs)

    @router.get("/providers")
    async def providers() -> dict[str, Any]:
        offered = {name: {"operator_key": name in lab.settings.operator_keys} for name in PROVIDERS}
        return {"providers": offered, "suites": ["paper", "all"], "max_turns": lab.settings.max_turns}

    @router.post("/chat")
    async def chat(body: ChatRequest, who: Caller = who_calls) -> StreamingResponse:
        choice = choose_model(body, lab.settings)
        lab.registry.acquire(who.owner)  # given back when the stream ends
        return StreamingResponse(chat_lines(lab, who, choice, body), media_type="application/x-ndjson")

    @router.post("/runs", status_code=202)
    async def start(body: RunRequest, who: Caller = who_calls) -> dict[str, Any]:
        choice = choose_model(body, lab.settings)
        target = lab.target
        plan = BenchmarkPlan(
            target.url, who.token, choice, body.bag, body.tasks, body.repeat, body.max_turns, target.transport()
        )
        return lab.registry.start(who.owner, plan).status()

    @router.get("/runs")
    async def mine(who: Caller = who_calls) -> dict[str, Any]:
        return {"runs": [{k: v for k, v in r.status().items() if k != "records"} for r in lab.registry.mine(who.owner)]}

    @router.get("/{run_id}")
    async def status(run_id: str, who: Caller = who_calls) -> dict[str, Any]:
        return lab.registry.get(who.owner, run_id).status()

    @router.post("/{run_id}/cancel")
    async def cancel(run_id: str, who: Caller = who_calls) -> dict[str, Any]:
        return lab.registry.cancel(who.owner, run_id).status()

    @router.get("/{run_id}/results")
    async def results(run_id: str, who: Caller = who_calls) -> JSONResponse:
        run = lab.registry.get(who.owner, run_id)
        headers = {"Content-Disposition": f'attachment; filename="{run_id}-results.json"'}
        return JSONResponse([r.model_dump(mode="json") for r in run.records], headers=headers)

    @router.get("/{run_id}/report")
    async def report(run_id: str, who: Caller = who_calls) -> Response:
        run = lab.registry.get(who.owner, run_id)
        text = render_report(run.records, _rows(run), [])
        return Response(text, media_type="text/markdown; charset=utf-8")

    @router.get("/{run_id}/{figure}")
    async def figure(run_id: str, figure: Literal["latency", "calls"], who: Caller = who_calls) -> Response:
        records = list(lab.registry.get(who.owner, run_id).records)  # the run may add more while this draws
        if not records:
            raise LabError("no run has finished yet; the figures come with the first result")
        labels = [model_label(r, records) for r in records]
        name = LATENCY_FIGURE if figure == "latency" else CALLS_FIGURE
        png = await anyio.to_thread.run_sync(lambda: figure_png(name, labels, records))
        return Response(png, media_type="image/png")

    return router
