"""The paper's figures as PNG: response time per model and tool calls per model (matplotlib's object API, no
pyplot state, so the page's requests may draw them on worker threads; about 0.2 s each)."""

from __future__ import annotations

import io
from collections.abc import Sequence
from pathlib import Path

from matplotlib.figure import Figure

from bagmcp_lab.results import RunRecord

LATENCY_FIGURE = "latency.png"
CALLS_FIGURE = "tool_calls.png"
FIGURES = (LATENCY_FIGURE, CALLS_FIGURE)


def _box(labels: list[str], values: list[list[float]], *, title: str, unit: str) -> bytes:
    figure = Figure(figsize=(max(4.0, 1.4 * len(labels) + 2), 3.6), dpi=100)
    axes = figure.subplots()
    axes.boxplot(values, tick_labels=labels, showmeans=True)
    axes.set_title(title)
    axes.set_ylabel(unit)
    axes.grid(axis="y", alpha=0.3)
    for label in axes.get_xticklabels():
        label.set_rotation(20)
        label.set_horizontalalignment("right")
    figure.tight_layout()
    buffer = io.BytesIO()
    figure.savefig(buffer, format="png")
    return buffer.getvalue()


def figure_png(name: str, labels: Sequence[str], records: Sequence[RunRecord]) -> bytes:
    """One figure (``LATENCY_FIGURE`` or ``CALLS_FIGURE``) as PNG; ``labels[i]`` is the model of ``records[i]``."""
    models = list(dict.fromkeys(labels))
    pairs = list(zip(records, labels, strict=True))
    if name == LATENCY_FIGURE:
        latency = [[r.latency_s for r, m in pairs if m == model] for model in models]
        return _box(models, latency, title="Response time per model", unit="seconds per task")
    calls = [[float(r.n_tool_calls) for r, m in pairs if m == model] for model in models]
    return _box(models, calls, title="Tool calls per model", unit="tool calls per task")


def draw_figures(out: Path, labels: Sequence[str], records: Sequence[RunRecord]) -> list[str]:
    """Write the figures into ``out``; their file names."""
    if not records:
        return []
    for name in FIGURES:
        (out / name).write_bytes(figure_png(name, labels, records))
    return list(FIGURES)
