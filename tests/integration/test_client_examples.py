"""The client examples of docs/CLIENTS.md, run as a user would against `bagmcp serve --token` and against
the team gateway of the test stack (a token restricted to two tools), and the Claude Desktop
configurations `bagmcp config --client desktop` prints.

The Python example runs on this venv's mcp 2.x. The TypeScript example and the Claude Desktop bridge
(`mcp-remote`) run from one `npm install` of examples/clients per session (from the npm registry, with
this machine's Node.js and no install scripts), into the pytest tmp dir; those tests skip with the
reason when node/npm are missing or too old, or the npm registry cannot be reached.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import anyio
import httpx
import pytest
from mcp import Client, StdioServerParameters

from bagmcp_kit.arguments import CONVENTIONS
from tests.fixtures import scenario as sc
from tests.fixtures.bagfactory import BagKind, write_bag
from tests.fixtures.mcp_client import call
from tests.fixtures.processes import BIN, http_ok, service, wait_until
from tests.fixtures.servers import free_port
from tests.integration.stack import Stack, bagmcp, new_token

ROOT = Path(__file__).resolve().parents[2]
TS_CALL_TOOL = Path(__file__).with_name("ts_call_tool.mjs")
EXAMPLES = ROOT / "examples" / "clients"
DOC = ROOT / "docs" / "CLIENTS.md"
TOKEN = "client-example-token"
BAG = "scenario"
INFO_LINE = f"{BAG}: {sum(sc.COUNTS.values())} messages on {len(sc.COUNTS)} topics"
UNKNOWN_BAG_ERROR = "bag_info failed: Error executing tool bag_info: no bag called 'scenari0'; did you mean: scenario?"
RUN_TIMEOUT_S = 60
NPM_INSTALL_TIMEOUT_S = 300
OFFLINE_CODES = ("ENOTFOUND", "EAI_AGAIN", "ECONNREFUSED", "ECONNRESET", "ETIMEDOUT", "ENETUNREACH", "EHOSTUNREACH")
NODE_MAJOR_MIN = 20


@pytest.fixture(scope="module")
def bag_folder(tmp_path_factory: pytest.TempPathFactory) -> Path:
    folder = tmp_path_factory.mktemp("client-bags")
    write_bag("ros1", folder)
    return folder


@pytest.fixture(scope="module")
def mcp_url(bag_folder: Path, tmp_path_factory: pytest.TempPathFactory) -> Iterator[str]:
    """`bagmcp serve --token` over the folder, once the bag is ingested; yields the MCP endpoint."""
    port = free_port()
    base = f"http://127.0.0.1:{port}"
    data = tmp_path_factory.mktemp("client-data")
    command = [str(BIN / "bagmcp"), "serve", "--bags", str(bag_folder), "--port", str(port)]
    command += ["--data", str(data), "--token", TOKEN]
    logs = tmp_path_factory.mktemp("client-logs")
    with service("bagmcp-serve-clients", command, env={}, log_dir=logs, ready=http_ok(f"{base}/healthz")):
        wait_until(lambda: _bag_ready(base), timeout_s=60, what=f"bag {BAG!r} to be ingested")
        yield f"{base}/mcp"


def _bag_ready(base: str) -> bool:
    answer = httpx.get(f"{base}/api/v1/bags/{BAG}", headers={"Authorization": f"Bearer {TOKEN}"}, timeout=5)
    return answer.status_code == 200 and answer.json()["status"] == "ready"


@pytest.fixture(scope="session")
def node_examples(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A copy of examples/clients with its npm dependencies installed (once per session)."""
    if shutil.which("node") is None or shutil.which("npm") is None:
        pytest.skip("node and npm are not installed: the TypeScript example and mcp-remote cannot run")
    major = int(_run(["node", "--version"], cwd=EXAMPLES).stdout.strip().lstrip("v").split(".")[0])
    if major < NODE_MAJOR_MIN:
        pytest.skip(f"node {major} is too old for the examples (they need node {NODE_MAJOR_MIN} or newer)")
    copy = tmp_path_factory.mktemp("node-examples") / "clients"
    shutil.copytree(EXAMPLES, copy, ignore=shutil.ignore_patterns("node_modules", "package-lock.json"))
    _npm_install(copy)
    return copy


def _npm_install(directory: Path) -> None:
    command = ["npm", "install", "--no-audit", "--no-fund", "--no-package-lock", "--ignore-scripts", "--prefer-offline"]
    try:
        done = _run(command, cwd=directory, timeout_s=NPM_INSTALL_TIMEOUT_S)
    except subprocess.TimeoutExpired:
        pytest.skip(f"npm install took over {NPM_INSTALL_TIMEOUT_S} s (no network to the npm registry?)")
    if done.returncode == 0:
        return
    output = done.stdout + done.stderr
    offline = [code for code in OFFLINE_CODES if code in output]
    if offline:
        pytest.skip(f"npm install could not reach the npm registry ({offline[0]}): the TypeScript example is not run")
    pytest.fail(f"npm install failed:\n{output[-3000:]}")


def _run(
    command: list[str], *, cwd: Path, env: dict[str, str] | None = None, timeout_s: float = RUN_TIMEOUT_S
) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        command, cwd=cwd, env={**os.environ, **(env or {})}, capture_output=True, text=True, timeout=timeout_s
    )


def _run_example(command: list[str], *, cwd: Path, url: str) -> subprocess.CompletedProcess[str]:
    return _run(command, cwd=cwd, env={"BAGMCP_URL": url, "BAGMCP_TOKEN": TOKEN})


def _listed_tools(stdout: str) -> list[str]:
    line = next(line for line in stdout.splitlines() if line.startswith("tools: "))
    return line.removeprefix("tools: ").split(", ")


def _check_answer(done: subprocess.CompletedProcess[str]) -> None:
    assert done.returncode == 0, done.stderr
    tools = _listed_tools(done.stdout)
    assert {"list_bags", "bag_info", "describe_topic", "get_job"} <= set(tools)
    assert len(tools) == len(set(tools))
    assert done.stdout.splitlines()[-1] == INFO_LINE


def test_the_python_example_lists_the_tools_and_reads_bag_info_with_the_token(mcp_url: str) -> None:
    done = _run_example([sys.executable, str(EXAMPLES / "python_client.py"), BAG], cwd=EXAMPLES, url=mcp_url)
    _check_answer(done)


def test_the_python_example_prints_the_tool_error_for_an_unknown_bag(mcp_url: str) -> None:
    done = _run_example([sys.executable, str(EXAMPLES / "python_client.py"), "scenari0"], cwd=EXAMPLES, url=mcp_url)
    assert done.returncode == 1
    assert done.stderr.strip() == UNKNOWN_BAG_ERROR


def test_the_typescript_example_lists_the_same_tools_and_reads_bag_info_with_the_token(
    mcp_url: str, node_examples: Path
) -> None:
    done = _run_example(["node", "typescript_client.mjs", BAG], cwd=node_examples, url=mcp_url)
    _check_answer(done)
    python = _run_example([sys.executable, str(EXAMPLES / "python_client.py"), BAG], cwd=EXAMPLES, url=mcp_url)
    assert _listed_tools(done.stdout) == _listed_tools(python.stdout)


def test_the_typescript_example_gets_an_error_result_for_an_unknown_bag(mcp_url: str, node_examples: Path) -> None:
    done = _run_example(["node", "typescript_client.mjs", "scenari0"], cwd=node_examples, url=mcp_url)
    assert done.returncode == 1  # set only on result.isError; a thrown error would print a stack trace
    assert done.stderr.strip() == UNKNOWN_BAG_ERROR


def test_the_typescript_example_without_the_token_is_refused(mcp_url: str, node_examples: Path) -> None:
    done = _run(["node", "typescript_client.mjs", BAG], cwd=node_examples, env={"BAGMCP_URL": mcp_url})
    assert done.returncode == 1
    assert "401" in done.stderr
    assert "tools:" not in done.stdout


def test_the_typescript_sdk_through_the_gateway_sees_a_restricted_token_s_tools_and_is_refused_others(
    stack: Stack, uploaded: dict[BagKind, dict[str, Any]], node_examples: Path
) -> None:
    assert uploaded["ros1"]["name"] == BAG
    token = new_token(stack, "typescript-client", "--allow", "list_bags", "--allow", "bag_info")
    env = {"BAGMCP_URL": f"{stack.url}/mcp", "BAGMCP_TOKEN": token}
    done = _run(["node", "typescript_client.mjs", BAG], cwd=node_examples, env=env)
    assert done.returncode == 0, done.stderr
    assert _listed_tools(done.stdout) == ["list_bags", "bag_info"]
    assert done.stdout.splitlines()[-1] == INFO_LINE
    shutil.copy(TS_CALL_TOOL, node_examples)
    denied = _run(["node", TS_CALL_TOOL.name, "plot_2d", json.dumps({"bag": BAG})], cwd=node_examples, env=env)
    assert denied.returncode == 0, denied.stderr
    answer = json.loads(denied.stdout)
    assert answer["isError"] is True
    assert answer["text"].startswith("plot_2d is not enabled for this token")
    assert CONVENTIONS in answer["instructions"]


def _desktop_server(
    name: str, replacements: dict[str, str], *, env: dict[str, str], cwd: Path | None = None
) -> StdioServerParameters:
    """One entry of examples/clients/claude_desktop_config.json with its placeholders filled in."""
    raw = (EXAMPLES / "claude_desktop_config.json").read_text()
    for placeholder, value in replacements.items():
        raw = raw.replace(placeholder, value)
    entry = json.loads(raw)["mcpServers"][name]
    return StdioServerParameters(
        command=entry["command"], args=entry["args"], env={**entry.get("env", {}), **env}, cwd=cwd
    )


async def _bag_info_when_ready(params: StdioServerParameters, *, ingested: bool = False) -> dict[str, object]:
    """Connect as Claude Desktop does (initialize, protocol 2025-11-25); wait for the bag (unless it is
    ``ingested`` already); ask bag_info."""
    with anyio.fail_after(RUN_TIMEOUT_S):
        async with Client(params, cache=None, mode="legacy") as client:
            while not ingested and await _statuses(client) != ["ready"]:
                await anyio.sleep(0.2)
            return await call(client, "bag_info", bag=BAG)


async def _statuses(client: Client) -> list[str]:
    return [b["status"] for b in (await call(client, "list_bags", name=BAG))["bags"]]


@pytest.mark.anyio
async def test_the_claude_desktop_stdio_configuration_answers_bag_info(bag_folder: Path, tmp_path: Path) -> None:
    replacements = {"/path/to/bagmcp/.venv/bin/bagmcp": str(BIN / "bagmcp"), "/path/to/bags": str(bag_folder)}
    env = {"BAGMCP_DATA_DIR": str(tmp_path)} | {k: v for k, v in os.environ.items() if k == "PYTHONPATH"}
    info = await _bag_info_when_ready(_desktop_server("bags", replacements, env=env))
    assert info["message_count"] == sum(sc.COUNTS.values())


@pytest.mark.anyio
async def test_the_claude_desktop_mcp_remote_configuration_sends_the_token(
    mcp_url: str, node_examples: Path, tmp_path: Path
) -> None:
    replacements = {"https://bagmcp.example.com/mcp": mcp_url, "your-token": TOKEN}
    env = {"MCP_REMOTE_CONFIG_DIR": str(tmp_path), "npm_config_offline": "true"}  # npx runs the installed copy
    info = await _bag_info_when_ready(_desktop_server("team-bags", replacements, env=env, cwd=node_examples))
    assert info["message_count"] == sum(sc.COUNTS.values())


def _printed_entry(*arguments: str) -> dict[str, Any]:
    """The one server entry of what `bagmcp config --client desktop ...` prints."""
    printed = bagmcp("config", "--client", "desktop", *arguments)
    assert printed.returncode == 0, printed.stderr
    entries = json.loads(printed.stdout)["mcpServers"]
    assert list(entries) == ["bagmcp"]
    return dict(entries["bagmcp"])


@pytest.mark.anyio
async def test_bagmcp_config_for_claude_desktop_reaches_the_gateway_through_mcp_remote(
    stack: Stack, uploaded: dict[BagKind, dict[str, Any]], node_examples: Path, tmp_path: Path
) -> None:
    entry = _printed_entry("--url", f"{stack.url}/mcp", "--token", new_token(stack, "desktop-user"))
    env = {**entry["env"], "MCP_REMOTE_CONFIG_DIR": str(tmp_path), "npm_config_offline": "true"}
    params = StdioServerParameters(command=entry["command"], args=entry["args"], env=env, cwd=node_examples)
    info = await _bag_info_when_ready(params, ingested=True)
    assert info["message_count"] == sum(sc.COUNTS.values())


@pytest.mark.anyio
async def test_bagmcp_config_for_claude_desktop_over_stdio_answers_bag_info(bag_folder: Path, tmp_path: Path) -> None:
    entry = _printed_entry("--bags", str(bag_folder))
    env = {"BAGMCP_DATA_DIR": str(tmp_path)} | {k: v for k, v in os.environ.items() if k == "PYTHONPATH"}
    info = await _bag_info_when_ready(StdioServerParameters(command=entry["command"], args=entry["args"], env=env))
    assert info["message_count"] == sum(sc.COUNTS.values())


def _fenced_blocks(markdown: str) -> list[tuple[str, str]]:
    return re.findall(r"^```(\w*)\n(.*?)^```$", markdown, flags=re.MULTILINE | re.DOTALL)


def test_the_readme_shows_the_tested_python_and_typescript_examples_verbatim() -> None:
    blocks = _fenced_blocks((ROOT / "README.md").read_text())
    for name, language in [("python_client.py", "python"), ("typescript_client.mjs", "js")]:
        assert (language, (EXAMPLES / name).read_text()) in blocks, f"README.md does not show {name} verbatim"


def test_the_client_docs_show_the_tested_files_verbatim_and_only_valid_json() -> None:
    blocks = _fenced_blocks(DOC.read_text())
    for name, language in [
        ("python_client.py", "python"),
        ("typescript_client.mjs", "js"),
        ("package.json", "json"),
        ("claude_desktop_config.json", "json"),
    ]:
        assert (language, (EXAMPLES / name).read_text()) in blocks, f"docs/CLIENTS.md does not show {name} verbatim"
    for language, text in blocks:
        if language == "json":
            json.loads(text)
