"""results.json: one object per run with exactly the fields others script against."""

from __future__ import annotations

import json
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from pydantic import BaseModel, ValidationError

from bagmcp_lab.errors import LabError

RESULTS_FILE = "results.json"


class ToolCallOut(BaseModel):
    name: str
    arguments: dict[str, Any] | str
    ms: float
    is_error: bool


class RunRecord(BaseModel):
    task: str
    model: str
    provider: str
    repeat: int
    success: bool
    reason: str
    tool_calls: list[ToolCallOut]
    n_tool_calls: int
    latency_s: float
    input_tokens: int
    output_tokens: int
    final_answer: str


def write_results(directory: Path, records: Sequence[RunRecord]) -> Path:
    """Write atomically (a reader never sees half a file, also while a run adds records one by one)."""
    directory.mkdir(parents=True, exist_ok=True)
    path = directory / RESULTS_FILE
    partial = path.with_suffix(".json.partial")
    partial.write_text(json.dumps([r.model_dump(mode="json") for r in records], indent=2) + "\n")
    partial.replace(path)
    return path


def read_results(directory: Path) -> list[RunRecord]:
    path = directory / RESULTS_FILE if directory.is_dir() else directory
    try:
        raw = json.loads(path.read_text())
        return [RunRecord.model_validate(item) for item in raw]
    except FileNotFoundError:
        raise LabError(f"no {RESULTS_FILE} in {directory}; give the --out directory of a `bagmcp lab run`") from None
    except (ValueError, ValidationError, TypeError) as err:
        raise LabError(f"{path} is not a Lab results file ({str(err).splitlines()[0]})") from None
