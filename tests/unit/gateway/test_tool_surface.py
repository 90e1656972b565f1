"""The whole tool surface, as a model reads it on every turn: small, described, annotated.

Prints each tool's size (name + description + input schema, in characters) and the totals, and the whole
tools/list per profile as it is sent; the README states the same figures."""

from __future__ import annotations

import json
import re

import pytest
from mcp import Client
from mcp.types import Tool

from bagmcp_gateway.access.policy import ToolPolicy, listing_characters
from bagmcp_gateway.access.profiles import DEFAULT_PROFILES
from tests.fixtures.inprocess import InProcess

pytestmark = pytest.mark.anyio
AVERAGE_BUDGET, TOOL_BUDGET = 600, 1200
CORE_LISTING_BUDGET = 6000  # the whole tools/list of the core profile, for small models
CLIENT_CUT = 2048  # Claude Code keeps this many characters of each description and of the instructions


def model_reads(tool: Tool) -> int:
    return len(tool.name) + len(tool.description or "") + len(json.dumps(tool.input_schema, separators=(",", ":")))


async def _tools(served: InProcess) -> list[Tool]:
    async with Client(served.gateway(), cache=None) as client:
        return list((await client.list_tools()).tools)


async def test_every_tool_fits_the_size_budget_and_the_average_stays_under_it(served: InProcess) -> None:
    tools = await _tools(served)
    sizes = {t.name: model_reads(t) for t in tools}
    outputs = sum(len(json.dumps(t.output_schema, separators=(",", ":"))) for t in tools if t.output_schema)
    for name, size in sorted(sizes.items(), key=lambda item: -item[1]):
        print(f"{name:24} {size:5}")
    average = sum(sizes.values()) / len(sizes)
    print(f"{len(sizes)} tools, {sum(sizes.values())} characters ({average:.0f} a tool); output schemas {outputs}")
    assert max(sizes.values()) <= TOOL_BUDGET, sizes
    assert average <= AVERAGE_BUDGET


async def test_every_tool_sets_every_annotation_and_has_an_output_schema(served: InProcess) -> None:
    for tool in await _tools(served):
        hints = tool.annotations
        assert hints is not None, tool.name
        assert None not in (hints.read_only_hint, hints.destructive_hint, hints.idempotent_hint, hints.open_world_hint)
        assert tool.output_schema is not None, tool.name


async def test_every_argument_has_a_one_line_description(served: InProcess) -> None:
    for tool in await _tools(served):
        for name, schema in tool.input_schema.get("properties", {}).items():
            described = schema.get("description") or schema.get("enum") or isinstance(schema.get("default"), bool)
            assert described, f"{tool.name}.{name} has no description"
            assert "\n" not in schema.get("description", ""), f"{tool.name}.{name}"


async def test_schemas_carry_no_titles(served: InProcess) -> None:
    for tool in await _tools(served):
        assert '"title"' not in json.dumps(tool.input_schema).replace('"title": {', ""), tool.name


async def test_each_profile_s_whole_tools_list_is_printed_and_core_stays_small(served: InProcess) -> None:
    tools = await _tools(served)
    listings = {name: ToolPolicy().profile_listing(tools, name) for name in DEFAULT_PROFILES}
    for name, listing in listings.items():
        print(f"profile {name}: {len(listing)} tools, tools/list {listing_characters(listing):,} characters")
    assert [t.name for t in listings["full"]] == [t.name for t in tools]
    core = [t.name for t in listings["core"]]
    assert {"bag_info", "search_messages", "filter_bag", "plot_lidar_scan", "plot_histogram", "get_job"} <= set(core)
    assert len(core) == 12  # every tool of the paper's ten tasks (tests/checks/paper_tasks.py), and bag_info, get_job
    assert listing_characters(listings["core"]) < CORE_LISTING_BUDGET
    lean = {t.name: t for t in listings["core"]}
    assert lean["list_bags"].annotations is None  # hints for clients, not models
    assert "limit" not in lean["search_messages"].input_schema["properties"]  # a knob with a default


async def test_every_description_ends_with_an_example_call(served: InProcess) -> None:
    for tool in await _tools(served):
        ending = re.search(r"Example: [^\n]*\Z", (tool.description or "").rstrip())
        assert ending is not None, f"{tool.name}: the description does not end with an example"


async def test_descriptions_and_instructions_fit_what_clients_keep_conventions_first(served: InProcess) -> None:
    async with Client(served.gateway(), cache=None) as client:
        tools = list((await client.list_tools()).tools)
        instructions = client.instructions or ""
    print(f"instructions: {len(instructions)} characters")
    assert len(instructions) < CLIENT_CUT
    assert instructions.startswith("Bags: `bag` is an id, a name or a unique prefix")
    for profile in DEFAULT_PROFILES:
        for tool in ToolPolicy().profile_listing(tools, profile):
            assert len(tool.description or "") < CLIENT_CUT, (profile, tool.name)
