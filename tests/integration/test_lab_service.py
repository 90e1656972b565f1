"""The Lab's server side: chat turns and benchmark runs under /api/v1/lab, in process in `bagmcp serve` and as
a service of its own behind the stack's gateway, whose agent loops call the gateway's /mcp with the caller's
token (so the caller's profile applies). The key a request sends is used for that request and never logged."""

from __future__ import annotations

import base64
import json
import time
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import anyio
import httpx
import pytest

from bagmcp_gateway.access.profiles import CORE_TOOLS
from tests.fixtures.drive_bags import write_drive_bag
from tests.fixtures.lab_runs import PAPER_TASK_IDS, by_task, lab_run, results, served_folder
from tests.fixtures.processes import BIN, http_ok, service
from tests.fixtures.scripted_model import ScriptedModel, scripted_model_server
from tests.fixtures.servers import free_ports
from tests.integration.stack import OTHER_TOKEN, SERVICE_TOKEN, TOKEN, Stack, bagmcp, new_token, run_gateway

SERVE_TOKEN = "lab-serve-token"
PROMPT = "Plot linear and angular velocity from t=10 s to t=30 s. (bag: drive)"


@dataclass(frozen=True)
class LabServer:
    url: str  # what the page talks to: the embedded server or the stack's gateway
    token: str
    log: Path  # where the process running the Lab's agent loops logs
    bag: str
    service_url: str = ""  # the Lab service itself (team mode)


@pytest.fixture(scope="module")
def model() -> Iterator[ScriptedModel]:
    with scripted_model_server("lab-page-key-4f2a") as scripted:
        yield scripted


@pytest.fixture(scope="module")
def embedded(tmp_path_factory: pytest.TempPathFactory) -> Iterator[LabServer]:
    folder = tmp_path_factory.mktemp("lab-bags")
    write_drive_bag("ros1", folder)
    with served_folder(folder, tmp_path_factory.mktemp("lab"), name="lab-embedded", token=SERVE_TOKEN) as (url, log):
        yield LabServer(url, SERVE_TOKEN, log, "drive")


@pytest.fixture(scope="module")
def team(stack: Stack, model: ScriptedModel, tmp_path_factory: pytest.TempPathFactory) -> Iterator[LabServer]:
    """The Lab service and a gateway that routes /api/v1/lab to it, over the stack's services."""
    name = stack.upload_ok(write_drive_bag("ros2-mcap", tmp_path_factory.mktemp("lab-drive")), name="lab_drive")["name"]
    anyio.run(stack.wait_ready, [name])
    lab_port, gateway_port = free_ports(2)
    lab_env = {
        "BAGMCP_SERVICE_TOKEN": SERVICE_TOKEN,
        "BAGMCP_PORT": str(lab_port),
        "BAGMCP_LAB_GATEWAY_URL": f"http://127.0.0.1:{gateway_port}/mcp",
        "BAGMCP_LAB_BASE_URLS": model.anthropic_url,  # both wire formats: the scripted server only
    }
    urls = stack.service_urls
    routes = f"bags={urls['bag-store']},artifacts={urls['plotting']},lab=http://127.0.0.1:{lab_port}"
    lab_command = [str(BIN / "python"), "-m", "bagmcp_lab"]
    with (
        service(
            "lab", lab_command, env=lab_env, log_dir=stack.logs, ready=http_ok(f"http://127.0.0.1:{lab_port}/healthz")
        ),
        run_gateway(stack, "lab-gateway", gateway_port, {"BAGMCP_REST_ROUTES": routes}),
    ):
        yield LabServer(
            f"http://127.0.0.1:{gateway_port}", TOKEN, stack.logs / "lab.log", name, f"http://127.0.0.1:{lab_port}"
        )


def _model(model: ScriptedModel, provider: str = "openai", player: str = "capable") -> dict[str, Any]:
    base_url = model.openai_url if provider == "openai" else model.anthropic_url
    return {"provider": provider, "model": player, "base_url": base_url, "api_key": model.api_key}


def _api(server: LabServer, method: str, path: str, token: str | None = None, **options: Any) -> httpx.Response:
    headers = {"Authorization": f"Bearer {token or server.token}"}
    return httpx.request(method, f"{server.url}/api/v1/lab/{path}", headers=headers, timeout=60, **options)


def _chat(server: LabServer, body: dict[str, Any], token: str | None = None) -> list[dict[str, Any]]:
    headers = {"Authorization": f"Bearer {token or server.token}"}
    with httpx.stream("POST", f"{server.url}/api/v1/lab/chat", json=body, headers=headers, timeout=120) as answer:
        assert answer.status_code == 200, answer.read()
        return [json.loads(line) for line in answer.iter_lines()]


def _finish(server: LabServer, run_id: str, token: str | None = None) -> dict[str, Any]:
    deadline = time.monotonic() + 300
    while time.monotonic() < deadline:
        status: dict[str, Any] = _api(server, "GET", run_id, token).json()
        if status["state"] != "running":
            return status
        time.sleep(0.3)
    raise TimeoutError(f"Lab run {run_id} did not finish")


def _check_chat_turn_with_a_plot(server: LabServer, model: ScriptedModel) -> None:
    lines = _chat(server, {**_model(model), "prompt": PROMPT.replace("drive", server.bag)})
    assert [line["kind"] for line in lines] == ["tools", "call", "answer", "text", "done"]
    call, answer, done = lines[1], lines[2], lines[4]
    assert call["name"] == "plot_timeseries"
    assert call["arguments"]["start"] == 10.0
    assert answer["is_error"] is False
    assert answer["ms"] > 0
    assert base64.b64decode(answer["images"][0]["data"])[:8] == b"\x89PNG\r\n\x1a\n"
    assert "/cmd_vel.linear.x from 0 to 0.5" in done["final_answer"]
    assert done["tool_calls"][0]["name"] == "plot_timeseries"


def _check_a_run_fills_its_table(server: LabServer, model: ScriptedModel) -> str:
    started = _api(server, "POST", "runs", json={**_model(model, "anthropic"), "bag": server.bag})
    assert started.status_code == 202, started.text
    assert model.api_key not in started.text
    status = _finish(server, started.json()["run_id"])
    failed = {r["task"]: r["reason"] for r in status["records"] if not r["success"]}
    assert (status["state"], status["done"], status["planned"], failed) == ("succeeded", 10, 10, {})
    assert [t["id"].split("-")[0] for t in status["tasks"]] == PAPER_TASK_IDS
    downloaded = _api(server, "GET", f"{status['run_id']}/results")
    assert downloaded.headers["content-disposition"].endswith('-results.json"')
    assert [run["success"] for run in downloaded.json()] == [True] * 10
    report = _api(server, "GET", f"{status['run_id']}/report").text
    assert "| 3 | Trajectory summary | ✓ analyze_trajectory |" in report
    figure = _api(server, "GET", f"{status['run_id']}/calls")
    assert (figure.headers["content-type"], figure.content[:4]) == ("image/png", b"\x89PNG")
    return str(status["run_id"])


def test_embedded_chat_shows_each_tool_step_with_its_plot(embedded: LabServer, model: ScriptedModel) -> None:
    _check_chat_turn_with_a_plot(embedded, model)


def test_embedded_benchmark_runs_fill_their_table_and_are_bounded_per_token(
    embedded: LabServer, model: ScriptedModel
) -> None:
    _check_a_run_fills_its_table(embedded, model)
    _check_runs_are_bounded_per_token(embedded, model)


def _check_runs_are_bounded_per_token(server: LabServer, model: ScriptedModel, token: str | None = None) -> None:
    """Two runs going per token: the third is refused with 429 until one is cancelled."""
    body = {**_model(model), "bag": server.bag, "tasks": "all", "repeat": 3}
    first, second, third = (_api(server, "POST", "runs", token, json=body) for _ in range(3))
    assert (first.status_code, second.status_code, third.status_code) == (202, 202, 429)
    assert third.json()["error"]["message"].startswith("you already have 2 Lab runs or chats going")
    for run in (first, second):
        assert _api(server, "POST", f"{run.json()['run_id']}/cancel", token).status_code == 200
        assert _finish(server, run.json()["run_id"], token)["state"] == "cancelled"
    again = _api(server, "POST", "runs", token, json={**body, "repeat": 1, "tasks": "paper"})
    assert again.status_code == 202
    assert _api(server, "POST", f"{again.json()['run_id']}/cancel", token).status_code == 200


def test_embedded_lab_needs_the_token_and_never_logs_the_key(embedded: LabServer, model: ScriptedModel) -> None:
    refused = httpx.post(f"{embedded.url}/api/v1/lab/runs", json={**_model(model), "bag": "drive"}, timeout=30)
    assert refused.status_code == 401
    wrong = _chat(embedded, {**_model(model), "api_key": "not-the-key", "prompt": PROMPT})
    assert wrong[-1] == {"kind": "error", "message": "the model server answered 401: invalid x-api-key"}
    missing = _api(embedded, "POST", "chat", json={**_model(model), "api_key": None, "prompt": PROMPT})
    assert missing.status_code == 400
    assert missing.json()["error"]["message"] == "type your openai API key: this server has no operator key for it"
    assert model.api_key not in embedded.log.read_text()


def test_team_lab_chats_and_runs_through_the_gateway_with_the_callers_token(
    team: LabServer, model: ScriptedModel
) -> None:
    page = httpx.get(f"{team.url}/lab", timeout=30)  # the page is the gateway's; its API is the Lab service's
    assert (page.status_code, "script-src 'self'" in page.headers["content-security-policy"]) == (200, True)
    assert '<script src="/static/lab/lab.js" defer></script>' in page.text
    _check_chat_turn_with_a_plot(team, model)
    run_id = _check_a_run_fills_its_table(team, model)
    assert _api(team, "GET", run_id, OTHER_TOKEN).status_code == 404  # a run is its token's own
    direct = httpx.post(f"{team.service_url}/api/v1/lab/runs", headers={"Authorization": f"Bearer {TOKEN}"}, timeout=10)
    assert direct.status_code == 401  # the Lab service answers the gateway (service credential) only
    assert model.api_key not in team.log.read_text()


def test_team_lab_refuses_a_model_server_the_operator_did_not_allow(team: LabServer, model: ScriptedModel) -> None:
    body = {**_model(model), "base_url": "http://169.254.169.254/v1", "bag": "lab_drive"}
    refused = _api(team, "POST", "runs", json=body)
    assert refused.status_code == 400
    assert refused.json()["error"]["message"].startswith("this server may not call http://169.254.169.254/v1")


def test_a_core_profile_token_benchmarks_the_core_tools_only(
    stack: Stack, team: LabServer, model: ScriptedModel, tmp_path: Path
) -> None:
    """The model is offered the core profile's tools only; tasks whose references need other tools are skipped
    with the reason, and the paper's ten still succeed (the core profile holds what they need)."""
    core = new_token(stack, "lab-core", "--profile", "core", "--scopes", "read,upload")
    before = len(model.received)
    done = lab_run(
        model, f"{stack.url}/mcp", tmp_path, provider="openai", player="capable", bag=team.bag, token=core, tasks="all"
    )
    assert done.returncode == 0, done.stderr
    runs = by_task(results(tmp_path))
    assert list(runs) == [*PAPER_TASK_IDS, "o15"]
    assert {task: run["reason"] for task, run in runs.items() if not run["success"]} == {}
    for skipped in ("warnings", "transform", "image", "window"):
        assert f"bagmcp lab: skipped {skipped}: the reference call " in done.stderr
    assert "is not enabled for this token" in done.stderr
    listed = json.loads(bagmcp("tools", "--profile", "core", "--json").stdout)["tools"]
    offered = [{t["function"]["name"] for t in r.body["tools"]} for r in model.received[before:]]
    assert offered
    assert all(names == set(listed) for names in offered)


def test_team_lab_chat_offers_the_model_only_the_callers_profile_tools(
    stack: Stack, team: LabServer, model: ScriptedModel
) -> None:
    """The Lab service runs a chat's agent loop with the caller's token, not its own service credential: a
    read-only core-profile token's chat lists, and offers the model, the core tools less filter_bag (a tool that
    creates a bag needs the upload scope)."""
    made = stack.rest("POST", "tokens", json={"name": "lab-chat-core", "profile": "core", "scopes": ["read"]})
    assert made.status_code in (200, 201), made.text
    core = str(made.json()["token"])
    readable = sorted(set(CORE_TOOLS) - {"filter_bag"})
    before = len(model.received)
    lines = _chat(team, {**_model(model), "prompt": PROMPT.replace("drive", team.bag)}, core)
    assert [line["kind"] for line in lines] == ["tools", "call", "answer", "text", "done"]
    assert sorted(lines[0]["names"]) == readable
    assert (lines[1]["name"], lines[2]["is_error"]) == ("plot_timeseries", False)
    offered = [sorted(t["function"]["name"] for t in r.body["tools"]) for r in model.received[before:]]
    assert offered == [readable] * 2  # the question, then the answer after the plot


def test_team_lab_runs_are_bounded_per_token(team: LabServer, model: ScriptedModel) -> None:
    _check_runs_are_bounded_per_token(team, model, OTHER_TOKEN)
