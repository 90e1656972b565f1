"""`bagmcp tools --profile P` and `bagmcp config --client C`: the arguments (surface_actions.py and
client_configs.py do the work, imported only when their command runs)."""

from __future__ import annotations

import argparse
from pathlib import Path

from bagmcp_cli.urls import mcp_url
from bagmcp_gateway.access.profiles import PROFILE_NAMES

ACTIONS = "bagmcp_cli.surface_actions"


def add_surface_commands(commands: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    listing = commands.add_parser("tools", help="the tools a profile lists, and the size of its tools/list")
    listing.add_argument("--profile", default="full", choices=sorted(PROFILE_NAMES))
    listing.add_argument("--json", action="store_true")
    listing.set_defaults(handler=f"{ACTIONS}:tools")
    snippet = commands.add_parser("config", help="print an MCP client's configuration for a bagmcp URL and token")
    snippet.add_argument("--client", required=True, choices=["claude-code", "cursor", "desktop"])
    snippet.add_argument(
        "--url", default="http://127.0.0.1:8000/mcp", type=mcp_url, help="the server (gateway or bagmcp serve)"
    )
    snippet.add_argument("--token", help="the bearer token to send")
    snippet.add_argument("--name", default="bagmcp", help="the server's name in the client")
    snippet.add_argument("--bags", type=Path, help="instead of a URL: run bagmcp over stdio on this folder of bags")
    snippet.set_defaults(handler="bagmcp_cli.client_configs:config")
