"""Which package may import which: the gateway, the kit and the common library know no service, and
services do not import each other (only the CLI, which assembles embedded mode, imports them all). The
library imports no Celery (the runtime is the kit's), and inside a package no import runs back up: its
rooms (subpackages and top-level modules) import each other without a circle, and where a package declares
its floors, no room imports one on a higher floor."""

from __future__ import annotations

import ast
import tomllib
from collections.abc import Iterator
from functools import cache
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


WITH_CLI = {**PACKAGES, "bagmcp_cli": ROOT / "cli" / "bagmcp_cli"}
MODULES = "<top-level modules>"  # a floor: every top-level module of the package not named on another floor
# Each package's floors, lowest first (a floor is one room or several side by side); rooms not named here
# are held only to the no-circle rule. The library: plain modules (errors, settings, time, keys, the task
# seam), then storage, bag reading, catalog, index, bag access, jobs, and the helpers over opened bags.
FLOORS: dict[str, tuple[str | tuple[str, ...], ...]] = {
    "bagmcp_shared": (
        MODULES,
        "storage",
        "bags",
        ("catalog", "index"),
        "access",
        "jobs",
        ("flight_modes", "gps_metres", "topics"),
    ),
    "bagmcp_kit": ("web", "runtime"),
    "bagmcp_bag_store": ("fleet", "ingest", "queries", "tools"),
    "bagmcp_analysis": (("lidar", "logs", "tf", "trajectory"), "reports", "queries", "tools"),
    "bagmcp_plotting": ("drawing", "tools"),
    "bagmcp_lab": (("providers", "tasks"), "server"),
}


def imported_packages(source: Path) -> set[str]:
    """The top-level `bagmcp_*` packages a file imports (absolute imports only; relative ones stay inside)."""
    found: set[str] = set()
    for node in _nodes(source):
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
    source.write_text(
        "import os\nfrom bagmcp_bag_store.tools import x\nimport bagmcp_kit.job_info as j\nfrom . import y\n"
    )
    assert imported_packages(source) == {"bagmcp_bag_store", "bagmcp_kit"}


@cache
def _nodes(source: Path) -> list[ast.AST]:
    """Every node of a file, parsed once per run (three checks read each product file)."""
    return list(ast.walk(ast.parse(source.read_text(), filename=str(source))))


def imported_modules(source: Path, module: str) -> set[str]:
    """Dotted names a file imports, relative imports resolved against ``module`` (its own dotted name);
    ``from a.b import c`` gives ``a.b.c``, which is a module or a name in one (either way inside ``a.b``)."""
    package = module.split(".") if source.name == "__init__.py" else module.split(".")[:-1]
    found: set[str] = set()
    for node in _nodes(source):
        if isinstance(node, ast.Import):
            found.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                base = ".".join([*package[: len(package) - node.level + 1], *([node.module] if node.module else [])])
            found.update(f"{base}.{alias.name}" for alias in node.names)
    return found


def sources(package: str) -> Iterator[tuple[Path, str]]:
    """Every file of ``package`` with its dotted module name."""
    root = WITH_CLI[package]
    for path in sorted(root.rglob("*.py")):
        parts = path.relative_to(root).with_suffix("").parts
        yield path, ".".join([package, *(parts[:-1] if parts[-1] == "__init__" else parts)])


def room_of(module: str, package: str) -> str | None:
    """The room of a dotted name inside ``package``: its subpackage or top-level module (None: the package
    itself, or outside it)."""
    parts = module.split(".")
    return parts[1] if parts[0] == package and len(parts) > 1 else None


def arrows(package: str) -> dict[tuple[str, str], set[str]]:
    """Room -> room imports inside ``package``, each with the files that make it."""
    found: dict[tuple[str, str], set[str]] = {}
    for path, module in sources(package):
        room = room_of(module, package)
        for target in imported_modules(path, module):
            other = room_of(target, package)
            if room and other and other != room:
                found.setdefault((room, other), set()).add(str(path.relative_to(ROOT)))
    return found


def circles(edges: set[tuple[str, str]]) -> list[list[str]]:
    """The rooms on circles (strongly connected groups of more than one room), found by Tarjan's walk."""
    graph: dict[str, set[str]] = {}
    for start, end in edges:
        graph.setdefault(start, set()).add(end)
    order: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    found: list[list[str]] = []

    def visit(room: str) -> None:
        order[room] = low[room] = len(order)
        stack.append(room)
        for other in graph.get(room, set()):
            if other not in order:
                visit(other)
                low[room] = min(low[room], low[other])
            elif other in stack:
                low[room] = min(low[room], order[other])
        if low[room] == order[room]:
            group = stack[stack.index(room) :]
            del stack[stack.index(room) :]
            if len(group) > 1:
                found.append(sorted(group))

    for room in sorted(graph):
        if room not in order:
            visit(room)
    return found


Floors = tuple[str | tuple[str, ...], ...]


def floor_of(floors: Floors, root: Path, room: str) -> int | None:
    """The index of ``room``'s floor (None: not declared); a top-level module named on no floor is on the
    MODULES floor, if there is one."""
    rooms = [(floor,) if isinstance(floor, str) else floor for floor in floors]
    for index, names in enumerate(rooms):
        if room in names:
            return index
    if MODULES in floors and (root / f"{room}.py").exists():
        return floors.index(MODULES)
    return None


def upward(floors: Floors, root: Path, found: dict[tuple[str, str], set[str]]) -> set[str]:
    """The files whose import goes to a higher floor than their own."""
    return {
        f"{file} ({room} imports {other}, a higher floor)"
        for (room, other), files in found.items()
        if (low := floor_of(floors, root, room)) is not None
        and (high := floor_of(floors, root, other)) is not None
        and high > low
        for file in files
    }


@pytest.mark.parametrize("package", sorted(WITH_CLI))
def test_no_import_runs_back_up_inside_a_package(package: str) -> None:
    found = arrows(package)
    assert found, f"{package}: no imports between its rooms found under {WITH_CLI[package]}"
    closing = {
        f"{start} imports {end} in {sorted(found[start, end])}"
        for group in circles(set(found))
        for start in group
        for end in group
        if (start, end) in found
    }
    assert closing == set()
    assert upward(FLOORS.get(package, ()), WITH_CLI[package], found) == set()


def test_every_declared_room_exists() -> None:
    missing = {
        f"{package}: {room}"
        for package, floors in FLOORS.items()
        for floor in floors
        for room in ((floor,) if isinstance(floor, str) else floor)
        if room != MODULES
        and not (WITH_CLI[package] / room).is_dir()
        and not (WITH_CLI[package] / f"{room}.py").exists()
    }
    assert missing == set()


def test_the_library_imports_no_celery() -> None:
    files = list(sources("bagmcp_shared"))
    assert len(files) > 3
    using = {
        str(path.relative_to(ROOT))
        for path, module in files
        if any(name.split(".")[0] == "celery" for name in imported_modules(path, module))
    }
    assert using == set()
    dependencies = tomllib.loads((ROOT / "shared" / "pyproject.toml").read_text())["project"]["dependencies"]
    assert [name for name in dependencies if name.startswith("celery")] == []


def test_the_gateway_runs_no_celery_so_imports_no_runtime() -> None:
    """The gateway reaches Redis through the library; the kit's runtime would import Celery at its start."""
    files = list(sources("bagmcp_gateway"))
    assert len(files) > 10
    using = {
        str(path.relative_to(ROOT))
        for path, module in files
        for name in imported_modules(path, module)
        if name.split(".")[0] == "celery" or name.startswith("bagmcp_kit.runtime")
    }
    assert using == set()


def test_the_checks_see_a_circle_an_arrow_up_and_celery(tmp_path: Path) -> None:
    package = tmp_path / "probe"
    (package / "low").mkdir(parents=True)
    (package / "low" / "__init__.py").write_text("from ..high import thing\nfrom celery import Celery\n")
    (package / "high.py").write_text("from probe.low import other\n")
    module = "probe.low"
    assert imported_modules(package / "low" / "__init__.py", module) == {"probe.high.thing", "celery.Celery"}
    assert room_of("probe.high.thing", "probe") == "high"
    assert circles({("low", "high"), ("high", "low"), ("high", "base")}) == [["high", "low"]]
    assert circles({("high", "low"), ("low", "base")}) == []
    found = {("low", "high"): {"probe/low/__init__.py"}, ("high", "low"): {"probe/high.py"}}
    assert upward(("low", "high"), package, found) == {"probe/low/__init__.py (low imports high, a higher floor)"}
    assert upward((MODULES, "low"), package, found) == {"probe/high.py (high imports low, a higher floor)"}


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
    rooms = {path.name for path in GATEWAY.iterdir() if (path / "__init__.py").exists()}  # not a stale cache dir
    assert (top, rooms) == ({"__init__.py", "__main__.py", "app.py", "lifespan.py", "settings.py"}, set(GATEWAY_ROOMS))


def test_the_room_check_sees_a_crossing(tmp_path: Path) -> None:
    source = tmp_path / "probe.py"
    source.write_text("from bagmcp_gateway.settings import X\nimport bagmcp_gateway.access.auth\nfrom . import y\n")
    assert gateway_parts(source) == {"settings", "access"}
