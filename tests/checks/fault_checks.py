"""What every fault test ends with: nothing lost, nothing duplicated, no orphan objects, no temporary files
left, and every bag ready or failed with a reason."""

from __future__ import annotations

from pathlib import Path

from tests.fixtures.faults import FaultStack
from tests.fixtures.processes import scratch_leftovers


def expected_objects(records: list[dict[str, object]]) -> set[str]:
    """The objects the listed bags own: their files and registration, and once ready what ingest learned."""
    owned: set[str] = set()
    for record in records:
        bag_id = record["id"]
        files, index_files = record["files"], record["index_files"]
        assert isinstance(files, list)
        assert isinstance(index_files, list)
        owned |= {f"bags/{bag_id}/{name}" for name in files} | {f"catalog/{bag_id}.json"}
        if record["status"] == "ready":
            owned |= {f"indexes/{bag_id}/summary.json"} | {f"indexes/{bag_id}/columns/{n}" for n in index_files}
    return owned


def temporary_files(data_dirs: list[Path]) -> list[str]:
    """Scratch files and partial downloads left under the processes' data directories."""
    left = [f"{d.name}/{f}" for d in data_dirs for f in scratch_leftovers(d)]
    partials = [d / "cache" / ".partial" for d in data_dirs]
    return left + [str(f) for p in partials if p.is_dir() for f in p.rglob("*") if f.is_file()]


def check_consistent(stack: FaultStack) -> list[dict[str, object]]:
    """Every bag settled (ready, or failed with a reason), listed once, owning exactly its objects, and no
    process left temporary files behind; returns the full records."""
    listing = stack.rest("GET", "bags", params={"limit": 500}).json()["bags"]
    records = [stack.rest("GET", f"bags/{b['id']}").json() for b in listing]
    for record in records:
        assert record["status"] in ("ready", "failed"), record
        assert record["status"] == "ready" or record["error"], record
    assert len({r["id"] for r in records}) == len({r["name"] for r in records}) == len(records)
    assert set(stack.objects()) == expected_objects(records)
    assert temporary_files([stack.data_dir(p.name) for p in [*stack.services.values(), *stack.workers]]) == []
    return records
