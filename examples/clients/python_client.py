"""List bagmcp's tools and ask `bag_info` about one bag, with the MCP Python SDK 2.x.

Usage: BAGMCP_URL=http://127.0.0.1:8000/mcp BAGMCP_TOKEN=secret python python_client.py BAG
"""

import os
import sys

import anyio
import httpx2  # mcp 2.x is built on httpx2, not httpx
from mcp import Client
from mcp.client.streamable_http import streamable_http_client
from mcp.types import TextContent


async def main(bag: str) -> int:
    url = os.environ.get("BAGMCP_URL", "http://127.0.0.1:8000/mcp")
    token = os.environ.get("BAGMCP_TOKEN")
    headers = {"Authorization": f"Bearer {token}"} if token else {}
    http = httpx2.AsyncClient(headers=headers, timeout=httpx2.Timeout(30, read=300))
    async with http, Client(streamable_http_client(url, http_client=http)) as client:
        listing = await client.list_tools()
        print("tools:", ", ".join(tool.name for tool in listing.tools))
        result = await client.call_tool("bag_info", {"bag": bag})
    if result.is_error:  # a tool error: the text says what to do next
        print("bag_info failed:", *(c.text for c in result.content if isinstance(c, TextContent)), file=sys.stderr)
        return 1
    info = result.structured_content or {}
    print(f"{info['name']}: {info['message_count']} messages on {len(info['topics'])} topics")
    return 0


if __name__ == "__main__":
    sys.exit(anyio.run(main, sys.argv[1]))
