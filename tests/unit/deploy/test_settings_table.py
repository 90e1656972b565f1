"""The README's settings table names every ``BAGMCP_*`` variable the product code reads, and only those.

A variable is "read" when its name is a string constant in a product package (the settings readers take
the name as a literal: ``env.integer("BAGMCP_OPEN_BAGS", 32)``); error sentences that merely mention a
variable inside a longer text are not counted."""

from __future__ import annotations

import ast
import re
from functools import cache
from pathlib import Path

ROOT = Path(__file__).resolve().parents[3]
PRODUCT = ("shared", "kit", "gateway", "services", "lab", "cli")
NAME = re.compile(r"BAGMCP_[A-Z0-9_]+")
ROW = re.compile(r"^\| `(BAGMCP_[A-Z0-9_]+)` \|", re.MULTILINE)


@cache  # both tests read it: parsing every product file takes most of their time
def names_in_code() -> dict[str, Path]:
    found: dict[str, Path] = {}
    for folder in PRODUCT:
        for source in (ROOT / folder).rglob("*.py"):
            for node in ast.walk(ast.parse(source.read_text(), filename=str(source))):
                if isinstance(node, ast.Constant) and isinstance(node.value, str) and NAME.fullmatch(node.value):
                    found.setdefault(node.value, source.relative_to(ROOT))
    return found


def names_in_table() -> list[str]:
    readme = (ROOT / "README.md").read_text()
    section = readme.split("\n## Settings\n", 1)[1].split("\n## ", 1)[0]
    return ROW.findall(section)


def test_every_variable_the_code_reads_has_a_row() -> None:
    table = names_in_table()
    missing = {name: str(path) for name, path in names_in_code().items() if name not in table}
    assert missing == {}, "add these to the README's Settings table (default and meaning)"


def test_every_row_names_a_variable_the_code_reads_once() -> None:
    table = names_in_table()
    assert len(table) == len(set(table)), "a variable has two rows"
    assert sorted(set(table) - set(names_in_code())) == []
    assert len(table) >= 60  # the table is the section's, not an empty match
