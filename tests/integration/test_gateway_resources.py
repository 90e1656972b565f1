"""MCP resources through the gateway: the resource link of a plot's answer is read with resources/read
through the stack's gateway over HTTP (the same PNG as the REST download) and through the in-process
gateway `bagmcp serve` and `bagmcp stdio` use; an unknown artifact or URI is a clear error; a token
without the read scope, or one that may call no plotting tool, cannot read plots."""

from __future__ import annotations

import base64
from pathlib import Path
from typing import Any

import httpx
import pytest
from mcp import Client, MCPError
from mcp.types import BlobResourceContents, CallToolResult, ResourceLink

from tests.fixtures.bagfactory import BagKind
from tests.fixtures.inprocess import copy_bags, in_process
from tests.fixtures.mcp_client import http_client, text_of
from tests.integration.stack import TOKEN, Stack, new_token

pytestmark = pytest.mark.anyio
PLOTS = "bagmcp://artifacts/{artifact}"
SPEED = ["/odom.twist.twist.linear.x"]


def _link(answer: CallToolResult) -> ResourceLink:
    assert not answer.is_error, text_of(answer)
    links = [c for c in answer.content if isinstance(c, ResourceLink)]
    assert len(links) == 1, "a plot answers with one resource link"
    assert links[0].mime_type == "image/png"
    return links[0]


def _inline_png(answer: CallToolResult) -> bytes:
    return base64.b64decode(next(c.data for c in answer.content if c.type == "image"))


async def _read_png(client: Client, uri: str) -> bytes:
    contents = (await client.read_resource(uri)).contents
    assert len(contents) == 1
    blob = contents[0]
    assert isinstance(blob, BlobResourceContents)
    assert (blob.uri, blob.mime_type) == (uri, "image/png")
    return base64.b64decode(blob.blob)


async def _refusal(client: Client, uri: str) -> str:
    with pytest.raises(MCPError) as refused:
        await client.read_resource(uri)
    return refused.value.message


async def test_a_plot_link_reads_through_the_stack_gateway_as_the_rest_download(
    stack: Stack, uploaded: dict[BagKind, dict[str, Any]]
) -> None:
    async with http_client(f"{stack.url}/mcp", TOKEN) as client:
        templates = (await client.list_resource_templates()).resource_templates
        assert [t.uri_template for t in templates] == [PLOTS]
        answer = await client.call_tool("plot_timeseries", {"bag": uploaded["ros1"]["name"], "paths": SPEED})
        link = _link(answer)
        assert answer.structured_content is not None
        artifact = answer.structured_content["result"]["artifact"]
        assert link.uri == PLOTS.format(artifact=artifact["id"])
        png = await _read_png(client, link.uri)
    downloaded = httpx.get(artifact["url"], headers={"Authorization": f"Bearer {TOKEN}"})
    assert downloaded.status_code == 200
    assert png == downloaded.content == _inline_png(answer)
    assert png.startswith(b"\x89PNG")
    assert len(png) == artifact["bytes"]


async def test_an_unknown_artifact_or_uri_is_an_error_saying_what_to_read(stack: Stack) -> None:
    async with http_client(f"{stack.url}/mcp", TOKEN) as client:
        missing = await _refusal(client, PLOTS.format(artifact="0123456789abcdef01234567"))
        assert "no plot artifact '0123456789abcdef01234567'" in missing
        assert "plot again" in missing
        unknown = await _refusal(client, "file:///etc/passwd")
        assert "no resource 'file:///etc/passwd' is served here" in unknown
        assert "resources/templates/list" in unknown


async def test_tokens_that_may_not_read_or_plot_cannot_read_plot_artifacts(
    stack: Stack, uploaded: dict[BagKind, dict[str, Any]]
) -> None:
    async with http_client(f"{stack.url}/mcp", TOKEN) as client:
        answer = await client.call_tool("plot_timeseries", {"bag": uploaded["ros2-mcap"]["name"], "paths": SPEED})
        uri = _link(answer).uri
    uploader = new_token(stack, "resource-uploader", "--scopes", "upload")
    body = {"jsonrpc": "2.0", "id": 1, "method": "resources/read", "params": {"uri": uri}}
    refused = httpx.post(f"{stack.url}/mcp", json=body, headers={"Authorization": f"Bearer {uploader}"})
    assert refused.status_code == 403  # no read scope: the MCP endpoint itself is closed to it
    no_plots = new_token(stack, "resource-no-plots", "--deny", "plot_*", "--deny", "compare_runs")
    async with http_client(f"{stack.url}/mcp", no_plots) as client:
        assert (await client.list_resource_templates()).resource_templates == []
        message = await _refusal(client, uri)
        assert f"this token may not read '{uri}'" in message
        assert "plotting service" in message
    one_plot = new_token(stack, "resource-one-plot", "--allow", "plot_2d")
    async with http_client(f"{stack.url}/mcp", one_plot) as client:
        assert (await _read_png(client, uri)) == _inline_png(answer)


async def test_a_plot_link_reads_through_the_in_process_gateway(
    scenario_bags: dict[BagKind, Path], tmp_path: Path
) -> None:
    folder = copy_bags([scenario_bags["ros2-sqlite3"]], tmp_path / "bags")
    with in_process(folder, tmp_path / "data") as services:
        for mode in ("auto", "legacy"):  # the 2026-07-28 protocol (relayed as JSON) and the handshake era
            async with Client(services.gateway(), cache=None, mode=mode) as client:
                bag = (await client.call_tool("list_bags", {})).structured_content
                assert bag is not None
                answer = await client.call_tool("plot_timeseries", {"bag": bag["bags"][0]["name"], "paths": SPEED})
                assert (await _read_png(client, _link(answer).uri)) == _inline_png(answer)
                missing = await _refusal(client, PLOTS.format(artifact="feedfacefeedfacefeedface"))
                assert "no plot artifact 'feedfacefeedfacefeedface'" in missing
