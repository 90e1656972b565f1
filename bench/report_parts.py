"""Small pieces every part of the page uses: numbers, met or missed, markdown tables."""

from __future__ import annotations

from collections.abc import Iterator

from bench.floors import FLOORS

FLOOR_LABELS = {f.key: f.label for f in FLOORS}


def ms(value: float) -> str:
    return f"{value:,.1f}" if value < 100 else f"{value:,.0f}"


def yes(met: bool | None) -> str:
    return "" if met is None else ("met" if met else "**missed**")


def table(header: list[str], rows: list[list[str]]) -> Iterator[str]:
    yield "| " + " | ".join(header) + " |"
    yield "|" + "---|" * len(header)
    for row in rows:
        yield "| " + " | ".join(row) + " |"
    yield ""
