"""The whole tools/list of embedded mode, compared with a snapshot taken before issue 19 moved every tool
to one declaration: each tool's name, description, lean input schema (argument names, descriptions, bounds,
required list), annotations and output schema must stay as they were.

A change on purpose (a new tool, a reworded description) rewrites the snapshot:
``.venv/bin/python -m tests.unit.gateway.test_listing_snapshot`` and commit the diff with the change."""

from __future__ import annotations

import json
import sys
import tempfile
from pathlib import Path
from typing import Any

import anyio
import pytest
from mcp import Client

from tests.fixtures.inprocess import in_process

SNAPSHOT = Path(__file__).parent / "snapshots" / "embedded_tools.json"


async def _listing(folder: Path, data: Path) -> dict[str, Any]:
    with in_process(folder, data) as served:
        async with Client(served.gateway(), cache=None) as client:
            tools = (await client.list_tools()).tools
    return {
        t.name: {
            "description": t.description,
            "input_schema": t.input_schema,
            "required": sorted(t.input_schema.get("required", [])),
            "annotations": t.annotations.model_dump(mode="json", exclude_none=True) if t.annotations else None,
            "output_schema": t.output_schema,
        }
        for t in tools
    }


@pytest.mark.anyio
async def test_the_tool_listing_is_the_one_of_the_snapshot(tmp_path: Path) -> None:
    (tmp_path / "bags").mkdir()
    listing = await _listing(tmp_path / "bags", tmp_path / "data")
    recorded = json.loads(SNAPSHOT.read_text())
    assert sorted(listing) == sorted(recorded), "tools added or removed"
    for name, tool in recorded.items():
        assert json.loads(json.dumps(listing[name])) == tool, name


def _write() -> None:
    with tempfile.TemporaryDirectory() as scratch:
        (Path(scratch) / "bags").mkdir()
        listing = anyio.run(_listing, Path(scratch) / "bags", Path(scratch) / "data")
    SNAPSHOT.write_text(json.dumps(listing, indent=1, sort_keys=True) + "\n")
    print(f"{len(listing)} tools written to {SNAPSHOT}", file=sys.stderr)


if __name__ == "__main__":
    _write()
