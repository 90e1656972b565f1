"""Counts in one-line summaries read as people write them."""

from __future__ import annotations

from bagmcp_shared.wording import counted


def test_one_is_singular_and_every_other_count_plural() -> None:
    assert [counted(n, "log record") for n in (0, 1, 2)] == ["0 log records", "1 log record", "2 log records"]
    assert counted(3, "match", "matches") == "3 matches"
