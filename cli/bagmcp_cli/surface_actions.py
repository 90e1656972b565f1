"""What `bagmcp tools --profile P` (what a profile lists, and its size) and `bagmcp config --client C` (a
client's configuration for a server URL and token) do; imported when they run (surface_commands.py: arguments)."""

from __future__ import annotations

import argparse
import json
import shlex
import sys
import tempfile
from pathlib import Path

import anyio
from mcp import Client
from mcp.types import Tool

from bagmcp_cli.embedded import compose
from bagmcp_cli.settings import EmbeddedSettings
from bagmcp_gateway.access.policy import ToolPolicy, listing_characters, tool_characters
from bagmcp_gateway.mcp_front.aggregator import build_gateway_server


async def _listing(profile: str) -> list[Tool]:
    with tempfile.TemporaryDirectory(prefix="bagmcp-tools-") as tmp:
        composition = compose(EmbeddedSettings(Path(tmp), Path(tmp) / "data"))
        try:
            async with Client(build_gateway_server(composition.upstreams), cache=None) as client:
                tools = list((await client.list_tools()).tools)
        finally:
            composition.embedded.runner.shutdown()
    return ToolPolicy().profile_listing(tools, profile)


def tools(args: argparse.Namespace) -> int:
    listing = anyio.run(_listing, args.profile)
    size = listing_characters(listing)
    if args.json:
        print(json.dumps({"profile": args.profile, "tools": [t.name for t in listing], "characters": size}))
        return 0
    for tool in listing:
        print(f"{tool.name:24} {tool_characters(tool):6} characters")
    print(f"profile {args.profile}: {len(listing)} tools, tools/list is {size:,} characters")
    return 0


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
