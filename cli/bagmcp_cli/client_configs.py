"""`bagmcp config --client C`: an MCP client's configuration for a bagmcp URL and token, or for stdio on a
folder. Its own module with light imports: beside `bagmcp tools` (which composes every service) each
`bagmcp config` took 3.2 s to start, for a few lines of JSON; now under 0.1 s."""

from __future__ import annotations

import argparse
import json
import shlex
import sys
from pathlib import Path

MCP_REMOTE = "mcp-remote@0.15.1"  # the version docs/CLIENTS.md and its test use


def _bagmcp_command() -> str:
    """This installation's bagmcp command, as an absolute path (clients do not start it in your shell)."""
    beside = Path(sys.executable).parent / "bagmcp"
    return str(beside) if beside.exists() else "bagmcp"


def _remote_entry(url: str, token: str | None) -> dict[str, object]:
    """Claude Desktop's bridge to a URL: mcp-remote adds the header, the token comes from ``env``."""
    args = ["-y", MCP_REMOTE, url, *(["--header", "Authorization: Bearer ${BAGMCP_TOKEN}"] if token else [])]
    if url.startswith("http://") and not url.startswith(("http://127.0.0.1", "http://localhost")):
        args.append("--allow-http")
    return {"command": "npx", "args": args, **({"env": {"BAGMCP_TOKEN": token}} if token else {})}


def client_config(client: str, *, name: str, url: str, token: str | None, bags: Path | None) -> str:
    """What ``client`` needs to reach bagmcp: over stdio on ``bags`` when given, else at ``url``."""
    stdio = [_bagmcp_command(), "stdio", "--bags", str(bags.resolve())] if bags is not None else None
    if client == "claude-code":
        if stdio is not None:
            return shlex.join(["claude", "mcp", "add", name, "--", *stdio])
        header = ["--header", f"Authorization: Bearer {token}"] if token else []
        return shlex.join(["claude", "mcp", "add", "--transport", "http", name, url, *header])
    entry: dict[str, object]
    if stdio is not None:
        entry = {"command": stdio[0], "args": stdio[1:]}
    elif client == "cursor":
        entry = {"url": url, **({"headers": {"Authorization": f"Bearer {token}"}} if token else {})}
    else:
        entry = _remote_entry(url, token)
    return json.dumps({"mcpServers": {name: entry}}, indent=2)


def config(args: argparse.Namespace) -> int:
    print(client_config(args.client, name=args.name, url=args.url, token=args.token, bags=args.bags))
    return 0
