"""The gateway aggregates upstream MCP servers: schemas pass through, a down upstream drops out,
collisions need a prefix, progress is relayed. Upstreams are real MCPServers, in process."""

from __future__ import annotations

import shutil
from pathlib import Path

import anyio
import pytest
from mcp import Client
from mcp.server.mcpserver import Context, MCPServer
from mcp.types import SERVER_INFO_META_KEY

from bagmcp_gateway.mcp_front.aggregator import build_gateway_server
from bagmcp_gateway.upstreams.connections import Connections
from bagmcp_gateway.upstreams.upstream import GatewayConfigError, Upstream
from tests.fixtures.bagfactory import BagKind
from tests.fixtures.mcp_client import call, call_error, text_of
from tests.fixtures.processes import BIN, http_ok, service
from tests.fixtures.servers import free_port

pytestmark = pytest.mark.anyio


def _upstream_server(name: str) -> MCPServer:
    server = MCPServer(name)

    @server.tool()
    def topic_stats(topic: str, window: int = 10) -> dict[str, float]:
        """Mean of a topic over a window."""
        return {"mean": float(len(topic) * window)}

    @server.tool()
    async def long_scan(steps: int, ctx: Context) -> str:
        """Reports progress once per step."""
        for step in range(steps):
            await ctx.report_progress(step + 1, total=steps, message=f"step {step + 1}/{steps}")
        return f"scanned {steps}"

    return server


async def test_tools_keep_their_names_and_schemas_and_calls_reach_the_owner() -> None:
    upstream = _upstream_server("analysis")
    gateway = build_gateway_server([Upstream(name="analysis", server=upstream)])
    async with Client(gateway, cache=None) as client, Client(upstream, cache=None) as direct:
        via_gateway = {t.name: t for t in (await client.list_tools()).tools}
        original = {t.name: t for t in (await direct.list_tools()).tools}
        assert via_gateway["topic_stats"].input_schema == original["topic_stats"].input_schema
        assert via_gateway["topic_stats"].output_schema == original["topic_stats"].output_schema
        assert (await call(client, "topic_stats", topic="/odom", window=2))["mean"] == 10.0


async def test_answers_reach_callers_of_either_protocol_era_as_the_gateway_s() -> None:
    gateway = build_gateway_server([Upstream(name="analysis", server=_upstream_server("upstream-name"))], name="bagmcp")
    for mode in ("auto", "legacy"):  # 2026-07-28: relayed in wire form; 2025-11-25: through the SDK's handlers
        async with Client(gateway, cache=None, mode=mode) as client:
            answer = await client.call_tool("topic_stats", {"topic": "/odom", "window": 3})
            assert answer.structured_content == {"mean": 15.0}
            assert text_of(answer) == '{\n  "mean": 15.0\n}'
            stamp = (answer.meta or {}).get(SERVER_INFO_META_KEY)
            assert stamp == (None if mode == "legacy" else {"name": "bagmcp", "version": ""})


async def test_a_down_upstream_drops_out_while_the_others_keep_working() -> None:
    down = Upstream(name="plotting", url=f"http://127.0.0.1:{free_port()}/mcp", timeout_s=3)
    gateway = build_gateway_server([Upstream(name="analysis", server=_upstream_server("a")), down])
    async with Client(gateway, cache=None) as client:
        names = {t.name for t in (await client.list_tools()).tools}
        assert names == {"topic_stats", "long_scan"}
        assert (await call(client, "topic_stats", topic="/x"))["mean"] == 20.0
        unknown = await call_error(client, "plot_timeseries")
        assert "plotting" in unknown


async def test_colliding_tool_names_are_a_configuration_error_unless_prefixed() -> None:
    first, second = _upstream_server("a"), _upstream_server("b")
    clashing = build_gateway_server([Upstream(name="one", server=first), Upstream(name="two", server=second)])
    async with Client(clashing, cache=None) as client:
        with pytest.raises(Exception, match="published by one and two"):  # in process, the first listing is start-up
            await client.list_tools()
    prefixed = build_gateway_server(
        [Upstream(name="one", server=first), Upstream(name="two", server=second, prefix="two")]
    )
    async with Client(prefixed, cache=None) as client:
        names = {t.name for t in (await client.list_tools()).tools}
        assert names == {"topic_stats", "long_scan", "two__topic_stats", "two__long_scan"}
        assert (await call(client, "two__topic_stats", topic="ab", window=1))["mean"] == 2.0


async def test_progress_notifications_of_an_upstream_reach_the_client() -> None:
    gateway = build_gateway_server([Upstream(name="analysis", server=_upstream_server("a"))])
    seen: list[tuple[float, float | None, str | None]] = []

    async def on_progress(progress: float, total: float | None, message: str | None) -> None:
        seen.append((progress, total, message))

    async with Client(gateway, cache=None) as client:
        result = await client.call_tool("long_scan", {"steps": 3}, progress_callback=on_progress)
    assert text_of(result) == "scanned 3"
    assert seen == [(1.0, 3.0, "step 1/3"), (2.0, 3.0, "step 2/3"), (3.0, 3.0, "step 3/3")]


def test_upstream_names_are_validated() -> None:
    with pytest.raises(GatewayConfigError):
        Upstream(name="Bad_Name", url="http://x/mcp")


async def test_a_restarted_upstream_is_used_again_without_restarting_the_gateway(
    scenario_bags: dict[BagKind, Path], tmp_path: Path
) -> None:
    folder = tmp_path / "bags"
    folder.mkdir()
    shutil.copy(scenario_bags["ros1"], folder)
    port = free_port()
    command = [str(BIN / "bagmcp"), "serve", "--bags", str(folder), "--port", str(port), "--data", str(tmp_path / "d")]
    upstream = Upstream(name="bag-store", url=f"http://127.0.0.1:{port}/mcp", timeout_s=3)
    connections = Connections([upstream], retry_s=0.2)
    gateway = build_gateway_server([upstream], connections=connections)
    async with anyio.create_task_group() as group, Client(gateway, cache=None) as client:
        with service(
            "upstream-1", command, env={}, log_dir=tmp_path, ready=http_ok(f"http://127.0.0.1:{port}/healthz")
        ):
            await group.start(connections.run)
            with anyio.fail_after(10):
                while not connections.connected("bag-store"):
                    await anyio.sleep(0.05)
            assert (await call(client, "list_bags"))["total"] == 1
        down = await call_error(client, "list_bags")
        assert "unavailable" in down
        with anyio.fail_after(10):
            while connections.connected("bag-store"):  # the failed call made the gateway drop the client
                await anyio.sleep(0.05)
        with service(
            "upstream-2", command, env={}, log_dir=tmp_path, ready=http_ok(f"http://127.0.0.1:{port}/healthz")
        ):
            with anyio.fail_after(20):
                while (await client.call_tool("list_bags", {})).is_error:
                    await anyio.sleep(0.2)
            with anyio.fail_after(10):
                while not connections.connected("bag-store"):
                    await anyio.sleep(0.05)
            assert (await call(client, "list_bags"))["total"] == 1
        group.cancel_scope.cancel()
