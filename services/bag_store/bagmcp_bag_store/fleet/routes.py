"""``GET /api/v1/query?sql=...``: query_bags for notebooks, under the same rules (one SELECT over the views
the token's tools would show, the same time and memory limits), answering JSON (bounded like the tool's
rows, up to ``rest_max_rows``), CSV or Parquet (every row up to ``rest_max_rows``; the total and whether it
was cut in the ``X-Total-Rows`` and ``X-Truncated`` headers)."""

from __future__ import annotations

import io
from typing import Literal

import anyio
import pyarrow.csv as pacsv
from fastapi import APIRouter, Request
from fastapi.responses import Response

from bagmcp_bag_store.errors import QueryForbiddenError
from bagmcp_bag_store.fleet.answers import shaped
from bagmcp_bag_store.fleet.engine import Outcome
from bagmcp_bag_store.fleet.files import parquet_bytes
from bagmcp_bag_store.fleet.service import Fleet
from bagmcp_bag_store.fleet.views import views_for
from bagmcp_kit.identity import rest_callable_tools

Format = Literal["json", "csv", "parquet"]
JSON_BUDGET_BYTES = 8 * 2**20


def _body(outcome: Outcome, form: Format) -> tuple[bytes, str]:
    if form == "parquet":
        return parquet_bytes(outcome.table), "application/vnd.apache.parquet"
    if form == "csv":
        sink = io.BytesIO()
        pacsv.write_csv(outcome.table, sink)
        return sink.getvalue(), "text/csv"
    return shaped(outcome, budget_bytes=JSON_BUDGET_BYTES).model_dump_json().encode(), "application/json"


def build_query_router(fleet: Fleet) -> APIRouter:
    router = APIRouter(prefix="/api/v1")

    @router.get("/query")
    async def query(request: Request, sql: str, format: Format = "json") -> Response:
        tools = rest_callable_tools(request)
        if tools is not None and "query_bags" not in tools:
            raise QueryForbiddenError("this token may not call query_bags, so it may not query across bags over REST")
        rows = fleet.engine.limits.rest_max_rows
        outcome = await anyio.to_thread.run_sync(
            lambda: fleet.engine.run(sql, readable=views_for(tools), max_rows=rows)
        )
        body, media = await anyio.to_thread.run_sync(_body, outcome, format)
        truncated = outcome.table.num_rows < outcome.total_rows
        headers = {"X-Total-Rows": str(outcome.total_rows), "X-Truncated": str(truncated).lower()}
        return Response(body, media_type=media, headers=headers)

    return router
