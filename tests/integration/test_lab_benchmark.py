"""`bagmcp lab run` through the real SDKs, the real `bagmcp serve` and its services, against the scripted model
server: the capable model succeeds on the paper's ten tasks on the three formats of the drive bag (both wire
formats), the weak model's runs fail each for its own reason, and results.json and report.md say so."""

from __future__ import annotations

import json
import os
import subprocess
from collections.abc import Iterator
from pathlib import Path

import pytest
from PIL import Image

from tests.fixtures.bagfactory import BagKind
from tests.fixtures.drive_images import HEIGHT, IMAGE_TOPICS, WIDTH
from tests.fixtures.inprocess import copy_bags
from tests.fixtures.lab_runs import KEY_VARIABLE, PAPER_TASK_IDS, by_task, lab_run, results, served_folder
from tests.fixtures.processes import BIN
from tests.fixtures.scripted_model import ScriptedModel, scripted_model_server

NAMES = {"ros1": "drive", "ros2-sqlite3": "drive_db3", "ros2-mcap": "drive_mcap"}
RESULT_FIELDS = {
    "task", "model", "provider", "repeat", "success", "reason", "tool_calls", "n_tool_calls", "latency_s",
    "input_tokens", "output_tokens", "final_answer",
}  # fmt: skip


@pytest.fixture(scope="module")
def served(tmp_path_factory: pytest.TempPathFactory, drive_bags: dict[BagKind, Path]) -> Iterator[str]:
    """`bagmcp serve` over the drive bag in three formats; the MCP URL."""
    folder = copy_bags(list(drive_bags.values()), tmp_path_factory.mktemp("served") / "bags")
    with served_folder(folder, tmp_path_factory.mktemp("lab-serve"), name="lab-serve") as (url, _log):
        yield f"{url}/mcp"


@pytest.fixture(scope="module")
def model() -> Iterator[ScriptedModel]:
    with scripted_model_server() as scripted:
        yield scripted


@pytest.mark.parametrize("kind", list(NAMES))
def test_the_capable_model_succeeds_on_the_papers_ten_tasks_on_each_format(
    served: str, model: ScriptedModel, kind: BagKind, tmp_path: Path
) -> None:
    images_before = model.images_received()
    done = lab_run(model, served, tmp_path, provider="openai", player="capable", bag=NAMES[kind])
    assert done.returncode == 0, done.stderr
    assert model.images_received() - images_before >= 4  # the plots, as image_url parts after the tool messages
    runs = results(tmp_path)
    assert [run["task"].split("-")[0] for run in runs] == PAPER_TASK_IDS
    assert all(set(run) == RESULT_FIELDS for run in runs)
    assert [(run["task"], run["success"]) for run in runs] == [(run["task"], True) for run in runs], done.stderr
    assert all(run["n_tool_calls"] == len(run["tool_calls"]) >= 1 for run in runs)
    assert all(run["input_tokens"] > 0 and run["output_tokens"] > 0 and run["latency_s"] > 0 for run in runs)
    assert "10/10 runs succeeded" in done.stdout
    trajectory = by_task(runs)["p03"]
    assert trajectory["tool_calls"][0]["name"] == "analyze_trajectory"
    assert trajectory["tool_calls"][0]["arguments"] == {"bag": NAMES[kind]}
    assert "18.000 m" in trajectory["final_answer"]


def test_the_report_has_the_papers_table_per_model_figures_and_merges_runs(
    served: str, model: ScriptedModel, tmp_path: Path
) -> None:
    capable, weak = tmp_path / "capable", tmp_path / "weak"
    for out, player in ((capable, "capable"), (weak, "weak")):
        assert lab_run(model, served, out, provider="anthropic", player=player, bag="drive").returncode == 0
    report = (capable / "report.md").read_text()
    assert "| 3 | Trajectory summary | ✓ analyze_trajectory |" in report
    assert "| capable | anthropic | 10 | 100% |" in report
    for figure in ("latency.png", "tool_calls.png"):
        with Image.open(capable / figure) as image:
            assert (image.format, image.size[0] >= 400) == ("PNG", True)
    command = [str(BIN / "bagmcp"), "lab", "report", str(capable), str(weak), "--out", str(tmp_path / "both")]
    done = subprocess.run(command, capture_output=True, text=True, timeout=120, check=False)
    assert done.returncode == 0, done.stderr
    both = (tmp_path / "both" / "report.md").read_text()
    assert "| # | task | capable | weak |" in both
    assert "| 2 | Plot linear and angular velocity | ✓ plot_timeseries | ✗ +plot_2d |" in both
    assert "| weak | anthropic | 10 | 0% |" in both


def test_the_weak_models_runs_fail_each_for_its_reason(served: str, model: ScriptedModel, tmp_path: Path) -> None:
    done = lab_run(model, served, tmp_path, provider="openai", player="weak", bag="drive_mcap")
    assert done.returncode == 0, done.stderr
    runs = by_task(results(tmp_path))
    assert not any(run["success"] for run in runs.values())
    reasons = {task: run["reason"] for task, run in runs.items()}
    assert reasons["p01"].startswith("did not call list_bags (called no tool)")
    assert reasons["p02"].startswith("did not call plot_timeseries with start=10.0, end=30.0 (called plot_2d)")
    assert reasons["p03"].startswith("answer does not state total distance (m) = 18 ± 0.36 (numbers stated: 39")
    assert reasons["p04"].startswith("every call of plot_2d failed: the arguments of plot_2d are not a JSON object")
    assert runs["p04"]["tool_calls"] == [{"name": "plot_2d", "arguments": '{"bag": "', "ms": 0.0, "is_error": True}]
    assert "answer does not state closest distance (m) = 0.282843 ± 0.01" in reasons["p05"]
    assert reasons["p06"].startswith("did not call analyze_lidar_scan (called get_message_at_time)")
    assert reasons["p07"] == "did not call plot_histogram with path=linear.x (called plot_lidar_scan)"
    assert reasons["p08"].startswith("every call of get_tf_tree failed: the arguments of get_tf_tree are not a JSON")
    assert runs["p08"]["tool_calls"] == [{"name": "get_tf_tree", "arguments": '{"bag": "', "ms": 0.0, "is_error": True}]
    assert reasons["p09"].startswith("did not call filter_bag with include_topics=/cmd_vel (arguments were")
    assert reasons["p10"].startswith("answer does not state max commanded linear velocity (m/s) = 0.5 ± 0.005")
    assert "0/10 runs succeeded" in done.stdout


def test_the_harder_tasks_pass_with_images_sent_as_images_on_the_anthropic_wire(
    served: str, model: ScriptedModel, tmp_path: Path
) -> None:
    before = len(model.received)
    done = lab_run(model, served, tmp_path, provider="anthropic", player="capable", bag="drive_db3", tasks="all")
    assert done.returncode == 0, done.stderr
    runs = by_task(results(tmp_path))
    assert list(runs) == [*PAPER_TASK_IDS, "o11", "o12", "o13", "o14", "o15"]
    assert all(run["success"] for run in runs.values()), {k: r["reason"] for k, r in runs.items() if not r["success"]}
    calls = [c["name"] for c in runs["o15"]["tool_calls"]]  # the three drives, and the bag p09 made
    assert calls == ["list_bags"] + ["bag_info"] * (len(calls) - 1)
    assert len(calls) >= 4
    sent = [r.body for r in model.received[before:] if r.wire == "anthropic"]
    assert all("The MCP server's instructions:\n" in body["system"] for body in sent)  # as MCP hosts pass them
    images = [
        block
        for body in sent
        for message in body["messages"]
        if isinstance(message["content"], list)
        for result in message["content"]
        if result.get("type") == "tool_result"
        for block in result["content"]
        if block["type"] == "image"
    ]
    assert len(images) >= 4
    assert {block["source"]["media_type"] for block in images} == {"image/png"}


def test_a_task_file_adds_tasks_whose_references_come_from_the_tools(
    served: str, model: ScriptedModel, tmp_path: Path
) -> None:
    tasks = tmp_path / "mine.yaml"
    tasks.write_text(
        "tasks:\n"
        "  - id: trajectory-again\n"
        "    title: Distance driven\n"
        "    prompt: 'Trajectory summary for the whole bag: total distance, mean and max speed. (bag: {bag})'\n"
        "    requires: [[analyze_trajectory, plot_2d]]\n"
        "    facts:\n"
        "      - {label: distance, tool: analyze_trajectory, arguments: {bag: '{bag}'},\n"
        "         path: distance_2d_m, tolerance: 0.01}\n"
        "      - {label: a wrong distance, value: 99.5}\n"
    )
    done = lab_run(model, served, tmp_path / "out", provider="openai", player="capable", bag="drive", tasks=str(tasks))
    assert done.returncode == 0, done.stderr
    [run] = results(tmp_path / "out")
    assert run["task"] == "trajectory-again"
    assert run["reason"] == "answer does not state a wrong distance = 99.5 ± 0 (numbers stated: 18, 0.3, 0.5)"


def test_a_wrong_or_missing_key_is_one_clear_sentence(served: str, model: ScriptedModel, tmp_path: Path) -> None:
    wrong = lab_run(model, served, tmp_path, provider="anthropic", player="capable", bag="drive", key="not-the-key")
    assert wrong.returncode == 1
    assert wrong.stderr.strip().splitlines()[-1].startswith("bagmcp: error: Anthropic answered 401")
    assert "not-the-key" not in wrong.stderr + wrong.stdout
    command = [str(BIN / "bagmcp"), "lab", "run", "--url", served, "--provider", "openai", "--model", "m"]
    env = {k: v for k, v in os.environ.items() if k != "OPENAI_API_KEY"}
    missing = subprocess.run([*command, "--bag", "drive", "--out", str(tmp_path / "x")], capture_output=True,
                             text=True, env=env, timeout=60, check=False)  # fmt: skip
    assert missing.returncode == 1
    assert missing.stderr.strip() == (
        "bagmcp: error: set OPENAI_API_KEY to your openai API key (or name another variable with --api-key-env)"
    )
    assert KEY_VARIABLE not in json.dumps(missing.stderr)


def test_no_images_sends_an_openai_model_none_and_the_image_task_still_passes(
    served: str, model: ScriptedModel, tmp_path: Path
) -> None:
    """`--no-images` (models without vision): the image task from a task file on the OpenAI wire sends no
    image_url part, and passes on the tool's text (the capable test above sees the parts without the flag)."""
    topic, at = IMAGE_TOPICS["rgb8"]
    tasks = tmp_path / "image.yaml"
    tasks.write_text(
        "tasks:\n"
        "  - id: o13-image\n"
        "    title: An image and its size\n"
        f"    prompt: 'Show me the image on {topic} at t={at:g} s. What is its size in pixels? (bag: {{bag}})'\n"
        "    requires: [get_image_at_time]\n"
        "    facts:\n"
        f"      - {{label: width, tool: get_image_at_time, arguments: {{bag: '{{bag}}', topic: {topic}, time: {at}}},\n"
        "         path: width}\n"
    )
    before, asked = model.images_received(), len(model.received)
    done = lab_run(model, served, tmp_path / "out", provider="openai", player="capable", bag="drive",
                   tasks=str(tasks), extra=("--no-images",))  # fmt: skip
    assert done.returncode == 0, done.stderr
    [run] = results(tmp_path / "out")
    assert (run["success"], run["tool_calls"][0]["name"]) == (True, "get_image_at_time"), run["reason"]
    assert f"The image is {WIDTH} x {HEIGHT} pixels" in run["final_answer"]
    assert len(model.received) - asked == 2  # the question, then the answer after the tool's text
    assert model.images_received() == before
