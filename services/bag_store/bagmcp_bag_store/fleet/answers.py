"""query_bags' answer: rows as structured content (columns once, then one list per row), bounded by rows and
bytes with the total and ``truncated``, and a short text table for the summary line."""

from __future__ import annotations

import json

from pydantic import BaseModel, Field, JsonValue

from bagmcp_bag_store.fleet.engine import Outcome
from bagmcp_shared.jsonify import to_json

TABLE_ROWS = 12  # rows shown in the text table (the structured rows hold up to the byte budget)
_CELL_CHARS = 40


class QueryAnswer(BaseModel):
    columns: list[str]
    rows: list[list[JsonValue]] = Field(description="up to the row and byte limits, in the query's order")
    total_rows: int = Field(description="rows the query produced")
    truncated: bool
    bags_queried: int = Field(description="ready bags the views covered")
    missing_bags: list[str] = Field(default_factory=list, description="bags whose rows are not stored yet")
    elapsed_ms: float


def shaped(outcome: Outcome, *, budget_bytes: int) -> QueryAnswer:
    """The outcome's rows, as many as fit ``budget_bytes`` of JSON (strings cut to 400 characters)."""
    columns = list(outcome.table.column_names)
    rows: list[list[JsonValue]] = []
    used = 0
    for record in outcome.table.to_pylist():
        row = [to_json(record[c], max_items=32, max_text=400) for c in columns]
        used += len(json.dumps(row, separators=(",", ":"))) + 1
        if used > budget_bytes and rows:
            break
        rows.append(row)
    return QueryAnswer(
        columns=columns,
        rows=rows,
        total_rows=outcome.total_rows,
        truncated=len(rows) < outcome.total_rows,
        bags_queried=outcome.bags,
        missing_bags=outcome.missing,
        elapsed_ms=outcome.elapsed_ms,
    )


def _cell(value: JsonValue) -> str:
    if isinstance(value, float):
        text = f"{value:.6g}"
    else:
        text = json.dumps(value) if isinstance(value, list | dict) else str(value)
    text = text.replace("|", "/").replace("\n", " ")
    return text if len(text) <= _CELL_CHARS else text[: _CELL_CHARS - 1] + "…"


def text_table(answer: QueryAnswer) -> str:
    """A summary line, then the first rows as a pipe table."""
    shown = answer.rows[:TABLE_ROWS]
    more = f", showing {len(answer.rows)}" if answer.truncated else ""
    missing = f"; {len(answer.missing_bags)} bags not in the store yet" if answer.missing_bags else ""
    head = f"{answer.total_rows} rows over {answer.bags_queried} bags{more}{missing} ({answer.elapsed_ms:.0f} ms)"
    lines = [head, " | ".join(answer.columns), *(" | ".join(_cell(v) for v in row) for row in shown)]
    if len(answer.rows) > len(shown):
        lines.append(f"... {len(answer.rows) - len(shown)} more rows in the structured content")
    return "\n".join(lines)
