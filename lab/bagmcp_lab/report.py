"""report.md in the paper's table layout (tasks x models, a success mark with the tools each model used, the
extra ones marked +), then per model the success rate, median latency and tool calls, the reason of every
failure, and the figures. ``write_report`` merges the runs of several result directories."""

from __future__ import annotations

import json
import statistics
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from bagmcp_lab.figures import draw_figures
from bagmcp_lab.results import RunRecord
from bagmcp_lab.tasks.model import Task

REPORT_FILE = "report.md"
TASKS_FILE = "tasks.json"


@dataclass(frozen=True)
class TaskRow:
    id: str
    title: str
    required: frozenset[str]


def write_tasks(directory: Path, tasks: Sequence[Task]) -> None:
    """What each task asked and needed, for reports made later from results.json alone."""
    rows = [
        {"id": t.id, "title": t.title, "prompt": t.prompt, "required": sorted(t.required_tools), "suite": t.suite}
        for t in tasks
    ]
    directory.mkdir(parents=True, exist_ok=True)
    (directory / TASKS_FILE).write_text(json.dumps(rows, indent=2) + "\n")


def read_tasks(directories: Sequence[Path]) -> dict[str, TaskRow]:
    rows: dict[str, TaskRow] = {}
    for directory in directories:
        path = directory / TASKS_FILE
        if path.is_file():
            for row in json.loads(path.read_text()):
                rows.setdefault(row["id"], TaskRow(row["id"], row["title"], frozenset(row["required"])))
    return rows


def model_label(record: RunRecord, records: Sequence[RunRecord]) -> str:
    shared = {r.provider for r in records if r.model == record.model}
    return record.model if len(shared) == 1 else f"{record.model} ({record.provider})"


def _cell(runs: list[RunRecord], row: TaskRow | None) -> str:
    if not runs:
        return "–"
    wins = sum(r.success for r in runs)
    mark = ("✓" if wins else "✗") if len(runs) == 1 else f"{wins}/{len(runs)} {'✓' if wins == len(runs) else '✗'}"
    used: list[str] = []
    for call in (c for run in runs for c in run.tool_calls):
        if call.name not in used:
            used.append(call.name)
    required = row.required if row else frozenset()
    tools = [name if name in required or not required else f"+{name}" for name in used]
    return f"{mark} {' '.join(tools)}".strip()


def _median(values: Sequence[float]) -> float:
    return statistics.median(values) if values else 0.0


def render_report(records: Sequence[RunRecord], tasks: dict[str, TaskRow], figures: Sequence[str]) -> str:
    models = list(dict.fromkeys(model_label(r, records) for r in records))
    task_ids = list(dict.fromkeys(r.task for r in records))
    lines = ["# MCP Lab benchmark", "", f"{len(records)} runs of {len(task_ids)} tasks by {len(models)} models.", ""]
    lines += ["| # | task | " + " | ".join(models) + " |", "|---|---|" + "---|" * len(models)]
    for number, task_id in enumerate(task_ids, start=1):
        row = tasks.get(task_id)
        cells = [_cell([r for r in records if r.task == task_id and model_label(r, records) == m], row) for m in models]
        lines.append(f"| {number} | {row.title if row else task_id} | " + " | ".join(cells) + " |")
    lines += [
        "",
        "✓ success, ✗ failure (k/n over repeats); tools each model called, + marks tools beyond the required.",
        "",
    ]
    lines += ["## Per model", "", "| model | provider | runs | success rate | median latency (s) | median tool calls |"]
    lines.append("|---|---|---|---|---|---|")
    for model in models:
        runs = [r for r in records if model_label(r, records) == model]
        rate = sum(r.success for r in runs) / len(runs)
        latency = _median([r.latency_s for r in runs])
        calls = _median([float(r.n_tool_calls) for r in runs])
        lines.append(f"| {model} | {runs[0].provider} | {len(runs)} | {rate:.0%} | {latency:.2f} | {calls:g} |")
    failures = [r for r in records if not r.success]
    lines += ["", "## Failures", ""]
    lines += [f"- {model_label(r, records)}, {r.task} (repeat {r.repeat}): {r.reason}" for r in failures] or ["None."]
    lines += ["", "## Figures", ""] + [f"![{name}]({name})" for name in figures]
    return "\n".join(lines) + "\n"


def write_report(out: Path, records: Sequence[RunRecord], *, sources: Sequence[Path] = ()) -> Path:
    """report.md and its figures in ``out`` (task titles from the tasks.json of ``out`` and ``sources``)."""
    out.mkdir(parents=True, exist_ok=True)
    labels = [model_label(r, records) for r in records]
    figures = draw_figures(out, labels, records)
    path = out / REPORT_FILE
    path.write_text(render_report(records, read_tasks([out, *sources]), figures))
    return path
