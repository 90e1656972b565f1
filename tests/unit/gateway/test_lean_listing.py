"""A lean profile's listing: no output schemas, no annotations (hints for clients, not models), no tuning knobs
(optional arguments with a default), and argument descriptions several tools repeat (conventions) left to the
instructions."""

from __future__ import annotations

import mcp.types as types

from bagmcp_gateway.access.lean import lean_tools

READ = types.ToolAnnotations(read_only_hint=True, destructive_hint=False, idempotent_hint=True, open_world_hint=False)
STOPS = types.ToolAnnotations(read_only_hint=False, destructive_hint=True, idempotent_hint=True, open_world_hint=False)


def tool(name: str, hints: types.ToolAnnotations, **arguments: str) -> types.Tool:
    properties = {arg: {"type": "string", "description": text} for arg, text in arguments.items()}
    return types.Tool(
        name=name,
        input_schema={"type": "object", "properties": properties},
        output_schema={"type": "object", "properties": {"x": {"type": "number"}}},
        annotations=hints,
    )


def test_a_lean_listing_keeps_what_a_model_needs_and_drops_what_it_can_do_without() -> None:
    tools = [
        tool("a", READ, bag="bag id or name", topic="e.g. /odom"),
        tool("b", READ, bag="bag id or name", topic="e.g. /odom"),
        tool("c", READ, bag="bag id or name", field="path to test"),
        tool("stop", STOPS, job_id="from a tool's answer"),
    ]
    lean = {t.name: t for t in lean_tools(tools)}
    assert all(t.output_schema is None for t in lean.values())
    assert lean["a"].input_schema["properties"] == {
        "bag": {"type": "string"},
        "topic": tools[0].input_schema["properties"]["topic"],
    }
    assert lean["c"].input_schema["properties"]["field"] == {"type": "string", "description": "path to test"}
    assert lean["a"].annotations is None
    assert lean["stop"].annotations is None
    assert lean["stop"].input_schema == tools[3].input_schema


def test_knobs_with_a_default_are_left_out_and_arguments_without_one_stay() -> None:
    listed = types.Tool(
        name="search",
        input_schema={
            "type": "object",
            "properties": {
                "bag": {"type": "string"},
                "limit": {"type": "integer", "default": 20, "description": "matches to show"},
                "start": {"type": ["number", "string"]},
                "count": {"type": "integer", "default": 3},
            },
            "required": ["bag", "count"],
        },
    )
    kept = lean_tools([listed])[0].input_schema["properties"]
    assert list(kept) == ["bag", "start", "count"]  # a required argument stays whatever its default
