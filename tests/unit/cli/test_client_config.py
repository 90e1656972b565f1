"""`bagmcp config --client claude-code|cursor|desktop`: what each client needs, for a URL and token or for
a folder served over stdio. The Claude Desktop forms are the ones examples/clients/claude_desktop_config.json
shows (tested against real servers in tests/integration/test_client_examples.py)."""

from __future__ import annotations

import json
import shlex
import sys
from pathlib import Path

import pytest

from bagmcp_cli.main import main

ROOT = Path(__file__).resolve().parents[3]
DESKTOP_EXAMPLE = json.loads((ROOT / "examples" / "clients" / "claude_desktop_config.json").read_text())
URL, TOKEN = "https://bags.example.com/mcp", "bmcp_secret"
BAGMCP = str(Path(sys.executable).parent / "bagmcp")


def printed(capsys: pytest.CaptureFixture[str], *arguments: str) -> str:
    assert main(["config", *arguments]) == 0
    return capsys.readouterr().out


def test_claude_code_gets_one_command_with_the_url_and_the_token_header(capsys: pytest.CaptureFixture[str]) -> None:
    command = shlex.split(printed(capsys, "--client", "claude-code", "--url", URL, "--token", TOKEN))
    assert command == [
        "claude",
        "mcp",
        "add",
        "--transport",
        "http",
        "bagmcp",
        URL,
        "--header",
        f"Authorization: Bearer {TOKEN}",
    ]


def test_claude_code_gets_the_stdio_server_after_a_double_dash(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    command = shlex.split(printed(capsys, "--client", "claude-code", "--bags", str(tmp_path), "--name", "bags"))
    assert command == ["claude", "mcp", "add", "bags", "--", BAGMCP, "stdio", "--bags", str(tmp_path)]


def test_cursor_gets_a_url_entry_with_the_header(capsys: pytest.CaptureFixture[str]) -> None:
    config = json.loads(printed(capsys, "--client", "cursor", "--url", URL, "--token", TOKEN))
    assert config == {"mcpServers": {"bagmcp": {"url": URL, "headers": {"Authorization": f"Bearer {TOKEN}"}}}}


def test_claude_desktop_gets_the_tested_mcp_remote_bridge_with_the_token_in_env(
    capsys: pytest.CaptureFixture[str],
) -> None:
    config = json.loads(printed(capsys, "--client", "desktop", "--url", URL, "--token", TOKEN, "--name", "team-bags"))
    tested = json.loads(
        json.dumps(DESKTOP_EXAMPLE["mcpServers"]["team-bags"])
        .replace("https://bagmcp.example.com/mcp", URL)
        .replace("your-token", TOKEN)
    )
    assert config == {"mcpServers": {"team-bags": tested}}


def test_claude_desktop_over_plain_http_off_this_machine_allows_http(capsys: pytest.CaptureFixture[str]) -> None:
    config = json.loads(printed(capsys, "--client", "desktop", "--url", "http://10.0.0.5:8080/mcp"))
    entry = config["mcpServers"]["bagmcp"]
    assert entry == {"command": "npx", "args": ["-y", "mcp-remote@0.15.1", "http://10.0.0.5:8080/mcp", "--allow-http"]}


def test_claude_desktop_and_cursor_get_the_tested_stdio_entry_for_a_folder(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    tested = DESKTOP_EXAMPLE["mcpServers"]["bags"]
    expected = {"command": BAGMCP, "args": [a.replace("/path/to/bags", str(tmp_path)) for a in tested["args"]]}
    for client in ("desktop", "cursor"):
        config = json.loads(printed(capsys, "--client", client, "--bags", str(tmp_path), "--name", "bags"))
        assert config == {"mcpServers": {"bags": expected}}
