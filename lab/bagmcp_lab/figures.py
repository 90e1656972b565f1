"""The paper's figures as PNG: response time per model and tool calls per model (matplotlib, Agg; about 0.2 s
each)."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

from bagmcp_lab.results import RunRecord

LATENCY_FIGURE = "latency.png"
CALLS_FIGURE = "tool_calls.png"


def _box(path: Path, labels: list[str], values: list[list[float]], *, title: str, unit: str) -> None:
    figure, axes = plt.subplots(figsize=(max(4.0, 1.4 * len(labels) + 2), 3.6), dpi=100)
    try:
        axes.boxplot(values, tick_labels=labels, showmeans=True)
        axes.set_title(title)
        axes.set_ylabel(unit)
        axes.grid(axis="y", alpha=0.3)
        plt.setp(axes.get_xticklabels(), rotation=20, ha="right")
        figure.tight_layout()
        figure.savefig(path, format="png")
    finally:
        plt.close(figure)


def draw_figures(out: Path, labels: Sequence[str], records: Sequence[RunRecord]) -> list[str]:
    """Write the figures into ``out``; ``labels[i]`` is the model column of ``records[i]``."""
    models = list(dict.fromkeys(labels))
    if not models:
        return []
    latency = [[r.latency_s for r, m in zip(records, labels, strict=True) if m == model] for model in models]
    calls = [[float(r.n_tool_calls) for r, m in zip(records, labels, strict=True) if m == model] for model in models]
    _box(out / LATENCY_FIGURE, models, latency, title="Response time per model", unit="seconds per task")
    _box(out / CALLS_FIGURE, models, calls, title="Tool calls per model", unit="tool calls per task")
    return [LATENCY_FIGURE, CALLS_FIGURE]
