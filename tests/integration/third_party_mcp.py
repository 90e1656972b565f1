"""A third-party MCP server, as a team might add one behind the gateway: plain mcp 2.x, nothing of bagmcp.

Run as ``python third_party_mcp.py PORT``; it serves streamable HTTP at http://127.0.0.1:PORT/mcp without
authentication. Its ``bag_info`` clashes with bagmcp's on purpose (the gateway needs a prefix for it).
"""

from __future__ import annotations

import sys

import anyio
from mcp.server.mcpserver import Context, MCPServer

server = MCPServer("weather-station", instructions="Weather station readings. Readings are in SI units.")


@server.tool()
def echo(text: str, ctx: Context) -> str:
    """Say ``text`` back, and whether the request carried an Authorization header."""
    headers = {k.lower(): v for k, v in (ctx.headers or {}).items()}
    return f"{text} (authorization: {'present' if 'authorization' in headers else 'none'})"


@server.tool()
async def slow(seconds: float) -> str:
    """Answer after ``seconds``."""
    await anyio.sleep(seconds)
    return f"done after {seconds} s"


@server.tool()
def bag_info(bag: str) -> str:
    """Not bagmcp's bag_info: the weather when ``bag`` was recorded."""
    return f"sunny when {bag} was recorded"


@server.tool()
async def grow(name: str, ctx: Context) -> str:
    """Add a tool called ``name`` and announce that the tool list changed."""

    def added() -> str:
        return f"{name} was added at run time"

    server.add_tool(added, name=name, description=f"Added at run time as {name}.")
    await ctx.notify_tools_changed()
    return f"added {name}"


if __name__ == "__main__":
    server.run(transport="streamable-http", host="127.0.0.1", port=int(sys.argv[1]))
