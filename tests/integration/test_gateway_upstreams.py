"""The gateway over real HTTP with the stack's services and a third-party MCP server (a plain mcp 2.x
process, tests/integration/third_party_mcp.py): its prefix and its own time limit, tools an upstream adds
at run time, one instructions text, a deterministic tools/list, and change events shared by replicas."""

from __future__ import annotations

import time
from collections.abc import Callable, Iterator
from contextlib import AbstractContextManager
from pathlib import Path
from typing import Any

import anyio
import httpx
import pytest
from mcp import Client

from bagmcp_kit.arguments import CONVENTIONS
from tests.fixtures.mcp_client import call, http_client, text_of
from tests.fixtures.processes import BIN, service
from tests.fixtures.servers import free_port
from tests.integration.stack import SERVICE_TOKEN, SERVICES, TOKEN, Stack, run_gateway

pytestmark = pytest.mark.anyio
THIRD_PARTY = Path(__file__).with_name("third_party_mcp.py")
WEATHER_TOOLS = ["ext__echo", "ext__slow", "ext__bag_info", "ext__grow"]
WEATHER_LIMIT_S = 1.5
NO_POLLING = {"BAGMCP_UPSTREAM_POLL_S": "600"}  # only announcements (or a failed call) make it re-list


def _answers(url: str) -> Callable[[], bool]:
    def check() -> bool:
        try:
            httpx.get(url, timeout=2)
        except httpx.HTTPError:
            return False
        return True

    return check


def third_party(log_dir: Path) -> tuple[str, AbstractContextManager[Any]]:
    """The third-party server on a free port: its MCP URL and the context that runs it."""
    port = free_port()
    url = f"http://127.0.0.1:{port}/mcp"
    command = [str(BIN / "python"), str(THIRD_PARTY), str(port)]
    return url, service(f"third-party-{port}", command, env={}, log_dir=log_dir, ready=_answers(url))


def _with_weather(stack: Stack, weather_url: str) -> dict[str, str]:
    """bag-store, and the third-party server as ``weather``: no service token (!), prefix ext, own time limit."""
    store = stack.service_urls["bag-store"]
    return {"BAGMCP_UPSTREAMS": f"bag-store={store}/mcp,!weather={weather_url}@ext#{WEATHER_LIMIT_S}"}


@pytest.fixture(scope="module")
def weather_gateway(stack: Stack, tmp_path_factory: pytest.TempPathFactory) -> Iterator[str]:
    weather_url, running = third_party(tmp_path_factory.mktemp("third-party"))
    port = free_port()
    with running, run_gateway(stack, "gateway-weather", port, {**_with_weather(stack, weather_url), **NO_POLLING}):
        yield f"http://127.0.0.1:{port}"


async def names_of(url: str) -> list[str]:
    async with http_client(f"{url}/mcp", TOKEN) as client:
        return [t.name for t in (await client.list_tools()).tools]


async def _collect_changes(client: Client, events: list[str]) -> None:
    async with client.listen(tools_list_changed=True) as subscription:
        async for event in subscription:
            events.append(type(event).__name__)


async def test_a_third_party_server_joins_under_its_prefix_and_never_sees_the_service_token(
    weather_gateway: str,
) -> None:
    names = await names_of(weather_gateway)
    assert [n for n in names if n.startswith("ext__")][:4] == WEATHER_TOOLS
    assert "bag_info" in names  # bagmcp's own, beside the third party's ext__bag_info
    async with http_client(f"{weather_gateway}/mcp", TOKEN) as client:
        assert text_of(await client.call_tool("ext__bag_info", {"bag": "run1"})) == "sunny when run1 was recorded"
        assert text_of(await client.call_tool("ext__echo", {"text": "hi"})) == "hi (authorization: none)"
        assert (await call(client, "list_bags", limit=1))["offset"] == 0


async def test_a_slow_third_party_tool_stops_at_its_own_limit_naming_the_service_while_others_answer(
    weather_gateway: str,
) -> None:
    outcome: dict[str, Any] = {}
    async with http_client(f"{weather_gateway}/mcp", TOKEN) as client:

        async def slow_call() -> None:
            began = time.monotonic()
            outcome["result"] = await client.call_tool("ext__slow", {"seconds": 30})
            outcome["took_s"] = time.monotonic() - began

        async with anyio.create_task_group() as group:
            group.start_soon(slow_call)
            await anyio.sleep(0.3)
            assert text_of(await client.call_tool("ext__echo", {"text": "meanwhile"})).startswith("meanwhile")
            assert (await call(client, "list_bags", limit=1))["offset"] == 0
            assert "result" not in outcome  # the slow call is still waiting
        assert outcome["result"].is_error
        assert f"the weather service did not answer ext__slow within {WEATHER_LIMIT_S:g} s" in text_of(
            outcome["result"]
        )
        assert WEATHER_LIMIT_S <= outcome["took_s"] < 10
        assert text_of(await client.call_tool("ext__echo", {"text": "after"})).startswith("after")
    assert "ext__slow" in await names_of(weather_gateway)  # slow is not down


async def test_a_tool_an_upstream_adds_at_run_time_reaches_listening_clients_without_polling(
    weather_gateway: str,
) -> None:
    events: list[str] = []
    added: list[str] = []
    async with http_client(f"{weather_gateway}/mcp", TOKEN) as client, anyio.create_task_group() as group:
        group.start_soon(_collect_changes, client, events)
        with anyio.fail_after(30):
            while not events:  # the gateway's own stream to the upstream may still be opening: add again
                added.append(f"fresh_{len(added)}")
                assert text_of(await client.call_tool("ext__grow", {"name": added[-1]})) == f"added {added[-1]}"
                with anyio.move_on_after(3):
                    while not events:
                        await anyio.sleep(0.05)
        assert events[0] == "ToolsListChanged"
        names = [t.name for t in (await client.list_tools()).tools]
        assert f"ext__{added[-1]}" in names
        answer = text_of(await client.call_tool(f"ext__{added[-1]}", {}))
        assert answer == f"{added[-1]} was added at run time"
        group.cancel_scope.cancel()


async def test_tools_list_comes_in_configuration_order_then_each_upstream_s_own_order(stack: Stack) -> None:
    expected: list[str] = []
    for name in SERVICES:  # the stack's BAGMCP_UPSTREAMS order; the gateway's jobs tools come last
        async with http_client(f"{stack.service_urls[name]}/mcp", SERVICE_TOKEN) as direct:
            expected += [t.name for t in (await direct.list_tools()).tools]
    expected += ["get_job", "cancel_job"]
    assert await names_of(stack.url) == expected
    assert await names_of(stack.url) == expected


async def test_clients_of_the_gateway_read_one_instructions_text(stack: Stack) -> None:
    async with http_client(f"{stack.url}/mcp", TOKEN) as client:
        text = client.instructions
    assert text is not None
    assert text.count(CONVENTIONS) == 1  # every service states the conventions; the gateway says them once
    for name in SERVICES:
        async with http_client(f"{stack.service_urls[name]}/mcp", SERVICE_TOKEN) as direct:
            own = direct.instructions
        assert own is not None
        purpose = own.removesuffix(CONVENTIONS).strip()
        assert purpose
        assert text.index(CONVENTIONS) < text.index(purpose)  # the conventions first (clients cut long texts)


async def test_a_replica_tells_its_clients_about_a_change_another_replica_noticed(stack: Stack, tmp_path: Path) -> None:
    weather_url, running = third_party(tmp_path)
    running.__enter__()
    port_a, port_b = free_port(), free_port()
    both = _with_weather(stack, weather_url)
    events: list[str] = []
    with (
        run_gateway(stack, "replica-polling", port_a, {**both, "BAGMCP_UPSTREAM_POLL_S": "1"}),
        run_gateway(stack, "replica-not-polling", port_b, {**both, **NO_POLLING}),
    ):
        quiet = f"http://127.0.0.1:{port_b}"
        async with http_client(f"{quiet}/mcp", TOKEN) as client, anyio.create_task_group() as group:
            assert "ext__echo" in await names_of(quiet)
            group.start_soon(_collect_changes, client, events)
            await anyio.sleep(0.5)
            running.__exit__(None, None, None)  # only the polling replica notices by itself
            with anyio.fail_after(20):
                while not events:
                    await anyio.sleep(0.1)
                while "ext__echo" in await names_of(quiet):
                    await anyio.sleep(0.2)
            assert events[0] == "ToolsListChanged"
            assert "bag_info" in await names_of(quiet)
            group.cancel_scope.cancel()
