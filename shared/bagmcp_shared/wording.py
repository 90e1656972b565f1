"""Counts as people write them in the one-line summaries tools answer with: "1 log record", "3 stops"."""

from __future__ import annotations


def counted(count: int, noun: str, plural: str | None = None) -> str:
    """``counted(1, "stop")`` -> "1 stop"; ``counted(2, "match", "matches")`` -> "2 matches"."""
    return f"{count} {noun if count == 1 else (plural or noun + 's')}"
