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
