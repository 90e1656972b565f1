"""report.md in the paper's layout from results alone, results.json round trips, and the figures are PNGs."""

from __future__ import annotations

import io
from pathlib import Path

import pytest
from PIL import Image

from bagmcp_lab.errors import LabError
from bagmcp_lab.figures import CALLS_FIGURE, LATENCY_FIGURE, figure_png
from bagmcp_lab.report import TaskRow, model_label, render_report, write_report
from bagmcp_lab.results import RunRecord, ToolCallOut, read_results, write_results


def _run(
    task: str, model: str, success: bool, tools: list[str], *, provider: str = "openai", latency_s: float = 1.0
) -> RunRecord:
    calls = [ToolCallOut(name=t, arguments={"bag": "drive"}, ms=5.0, is_error=False) for t in tools]
    return RunRecord(
        task=task, model=model, provider=provider, repeat=1, success=success, reason="ok" if success else "why",
        tool_calls=calls, n_tool_calls=len(calls), latency_s=latency_s, input_tokens=10, output_tokens=5,
        final_answer="",
    )  # fmt: skip


RUNS = [
    _run("p03-trajectory", "big", True, ["analyze_trajectory"], latency_s=2.0),
    _run("p03-trajectory", "small", False, ["bag_info", "analyze_trajectory"], latency_s=4.0),
    _run("p04-plot-trajectory", "big", True, ["plot_2d"], latency_s=3.0),
    _run("p04-plot-trajectory", "small", False, [], latency_s=1.0),
]
ROWS = {
    "p03-trajectory": TaskRow("p03-trajectory", "Trajectory summary", frozenset({"analyze_trajectory"})),
    "p04-plot-trajectory": TaskRow("p04-plot-trajectory", "Plot the trajectory", frozenset({"plot_2d"})),
}


def test_the_table_has_a_row_per_task_and_a_column_per_model_with_extra_tools_marked() -> None:
    report = render_report(RUNS, ROWS, ["latency.png"])
    assert "| # | task | big | small |" in report
    assert "| 1 | Trajectory summary | ✓ analyze_trajectory | ✗ +bag_info analyze_trajectory |" in report
    assert "| 2 | Plot the trajectory | ✓ plot_2d | ✗ |" in report
    assert "| big | openai | 2 | 100% | 2.50 | 1 |" in report
    assert "| small | openai | 2 | 0% | 2.50 | 1 |" in report
    assert "- small, p03-trajectory (repeat 1): why" in report
    assert "![latency.png](latency.png)" in report


def test_repeats_show_successes_of_runs_and_a_model_on_two_providers_gets_both_names() -> None:
    repeated = [*RUNS[:1], RUNS[0].model_copy(update={"repeat": 2, "success": False})]
    assert "| 1 | Trajectory summary | 1/2 ✗ analyze_trajectory |" in render_report(repeated, ROWS, [])
    both = [RUNS[0], RUNS[0].model_copy(update={"provider": "anthropic"})]
    assert [model_label(r, both) for r in both] == ["big (openai)", "big (anthropic)"]


def test_results_round_trip_and_a_report_is_written_with_its_figures(tmp_path: Path) -> None:
    write_results(tmp_path, RUNS)
    assert read_results(tmp_path) == RUNS
    report = write_report(tmp_path, read_results(tmp_path))
    assert report.read_text().startswith("# MCP Lab benchmark\n\n4 runs of 2 tasks by 2 models.")
    for name in (LATENCY_FIGURE, CALLS_FIGURE):
        with Image.open(tmp_path / name) as image:
            assert (image.format, image.size) == ("PNG", (480, 360))


def test_a_figure_is_drawn_in_memory_for_the_page() -> None:
    png = figure_png(CALLS_FIGURE, [model_label(r, RUNS) for r in RUNS], RUNS)
    with Image.open(io.BytesIO(png)) as image:
        assert image.format == "PNG"


def test_a_directory_without_results_is_one_clear_sentence(tmp_path: Path) -> None:
    with pytest.raises(LabError, match=r"^no results.json in .*; give the --out directory of a `bagmcp lab run`$"):
        read_results(tmp_path)
    (tmp_path / "results.json").write_text('[{"task": 1}]')
    with pytest.raises(LabError, match="is not a Lab results file"):
        read_results(tmp_path)
