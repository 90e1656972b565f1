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
