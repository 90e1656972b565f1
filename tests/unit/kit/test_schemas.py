"""Lean schemas: pydantic's titles and null branches go, what a value may be stays."""

from __future__ import annotations

from pydantic import BaseModel, Field

from bagmcp_kit.schemas import lean_input, lean_output


class Inner(BaseModel):
    title: str
    value: float | None


class Arguments(BaseModel):
    bag: str = Field(description="bag id or name")
    start: float | str | None = None
    inner: Inner | None = None
    tags: list[str] | None = None


def test_input_schemas_lose_titles_and_null_branches_but_keep_a_field_called_title() -> None:
    lean = lean_input(Arguments.model_json_schema())
    assert lean["properties"]["bag"] == {"description": "bag id or name", "type": "string"}
    assert lean["properties"]["start"] == {"type": ["number", "string"]}
    assert lean["properties"]["tags"] == {"items": {"type": "string"}, "type": "array"}
    assert lean["properties"]["inner"] == {"$ref": "#/$defs/Inner"}
    assert set(lean["$defs"]["Inner"]["properties"]) == {"title", "value"}
    assert "title" not in lean["$defs"]["Inner"]
    assert lean["required"] == ["bag"]


def test_output_schemas_keep_null_as_a_type() -> None:
    lean = lean_output(Inner.model_json_schema())
    assert lean["properties"]["value"] == {"type": ["number", "null"]}
    assert lean["properties"]["title"] == {"type": "string"}


class Stamp(BaseModel):
    offset_s: float


class Window(BaseModel):
    start: Stamp
    end: Stamp | None = None
    note: Inner | None = Field(default=None, description="once only")


def test_output_schemas_drop_defaults_and_write_a_definition_used_once_in_place() -> None:
    lean = lean_output(Window.model_json_schema())
    assert lean["properties"]["note"] == {
        "anyOf": [
            {
                "properties": {"title": {"type": "string"}, "value": {"type": ["number", "null"]}},
                "required": ["title", "value"],
                "type": "object",
            },
            {"type": "null"},
        ],
        "description": "once only",
    }
    assert lean["properties"]["start"] == {"$ref": "#/$defs/Stamp"}  # used twice: stays a definition
    assert lean["$defs"] == {
        "Stamp": {"properties": {"offset_s": {"type": "number"}}, "required": ["offset_s"], "type": "object"}
    }
    assert "default" not in str(lean)
