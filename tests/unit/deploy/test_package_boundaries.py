"""Which package may import which: the gateway, the kit and the common library know no service, and
services do not import each other (only the CLI, which assembles embedded mode, imports them all)."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[3]
SERVICES = {"bagmcp_bag_store", "bagmcp_analysis", "bagmcp_plotting"}
PACKAGES = {
    "bagmcp_shared": ROOT / "shared" / "bagmcp_shared",
    "bagmcp_kit": ROOT / "kit" / "bagmcp_kit",
    "bagmcp_gateway": ROOT / "gateway" / "bagmcp_gateway",
    "bagmcp_bag_store": ROOT / "services" / "bag_store" / "bagmcp_bag_store",
    "bagmcp_analysis": ROOT / "services" / "analysis" / "bagmcp_analysis",
    "bagmcp_plotting": ROOT / "services" / "plotting" / "bagmcp_plotting",
    "bagmcp_lab": ROOT / "lab" / "bagmcp_lab",
}
ALLOWED = {
    "bagmcp_shared": {"bagmcp_shared"},
    "bagmcp_kit": {"bagmcp_kit", "bagmcp_shared"},
    "bagmcp_gateway": {"bagmcp_gateway", "bagmcp_kit", "bagmcp_shared"},
    **{service: {service, "bagmcp_kit", "bagmcp_shared"} for service in SERVICES},
    "bagmcp_lab": {"bagmcp_lab", "bagmcp_kit", "bagmcp_shared"},  # an MCP client of the gateway, like any other
}


def imported_packages(source: Path) -> set[str]:
    """The top-level `bagmcp_*` packages a file imports (absolute imports only; relative ones stay inside)."""
    found: set[str] = set()
    for node in ast.walk(ast.parse(source.read_text(), filename=str(source))):
        if isinstance(node, ast.Import):
            found.update(alias.name.split(".")[0] for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            found.add(node.module.split(".")[0])
    return {name for name in found if name.startswith("bagmcp_")}


@pytest.mark.parametrize("package", sorted(PACKAGES))
def test_a_package_imports_only_what_it_may(package: str) -> None:
    files = sorted(PACKAGES[package].rglob("*.py"))
    assert len(files) > 3, f"{package}: no sources found under {PACKAGES[package]}"
    crossings = {
        f"{path.relative_to(ROOT)} imports {name}"
        for path in files
        for name in imported_packages(path) - ALLOWED[package]
    }
    assert crossings == set()


def test_the_check_sees_a_crossing(tmp_path: Path) -> None:
    source = tmp_path / "probe.py"
    source.write_text("import os\nfrom bagmcp_bag_store.tools import x\nimport bagmcp_kit.jobs as j\nfrom . import y\n")
    assert imported_packages(source) == {"bagmcp_bag_store", "bagmcp_kit"}


GATEWAY = PACKAGES["bagmcp_gateway"]
# The gateway's rooms and the rooms each may import: access and upstreams stand alone, the MCP front is built on
# both, the REST front on all three; no room imports the modules at the top (app, lifespan, settings).
GATEWAY_ROOMS = {
    "access": {"access"},
    "upstreams": {"upstreams"},
    "mcp_front": {"mcp_front", "access", "upstreams"},
    "rest_front": {"rest_front", "mcp_front", "access", "upstreams"},
}


def gateway_parts(source: Path) -> set[str]:
    """What of the gateway a file imports: the room, or the top-level module (``bagmcp_gateway.<part>...``)."""
    found: set[str] = set()
    for node in ast.walk(ast.parse(source.read_text(), filename=str(source))):
        names = [alias.name for alias in node.names] if isinstance(node, ast.Import) else []
        if isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            names = [node.module]
        found.update(name.split(".")[1] for name in names if name.startswith("bagmcp_gateway."))
    return found


@pytest.mark.parametrize("room", sorted(GATEWAY_ROOMS))
def test_a_gateway_room_imports_only_the_rooms_below_it(room: str) -> None:
    files = sorted((GATEWAY / room).rglob("*.py"))
    assert len(files) > 3, f"gateway room {room}: no sources found"
    crossings = {
        f"{path.relative_to(ROOT)} imports bagmcp_gateway.{part}"
        for path in files
        for part in gateway_parts(path) - GATEWAY_ROOMS[room]
    }
    assert crossings == set()


def test_every_gateway_module_but_the_composition_is_in_a_room() -> None:
    top = {path.name for path in GATEWAY.glob("*.py")}
    rooms = {path.name for path in GATEWAY.iterdir() if path.is_dir() and path.name != "__pycache__"}
    assert (top, rooms) == ({"__init__.py", "__main__.py", "app.py", "lifespan.py", "settings.py"}, set(GATEWAY_ROOMS))


def test_the_room_check_sees_a_crossing(tmp_path: Path) -> None:
    source = tmp_path / "probe.py"
    source.write_text("from bagmcp_gateway.settings import X\nimport bagmcp_gateway.access.auth\nfrom . import y\n")
    assert gateway_parts(source) == {"settings", "access"}
