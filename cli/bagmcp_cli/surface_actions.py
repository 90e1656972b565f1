"""What `bagmcp tools --profile P` (what a profile lists, and its size) and `bagmcp config --client C` (a
client's configuration for a server URL and token) do; imported when they run (surface_commands.py: arguments)."""

from __future__ import annotations

import argparse
import json
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
