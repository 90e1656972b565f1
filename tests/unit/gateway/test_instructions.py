"""The gateway's instructions: each upstream's sentences once, what they share (the conventions) before what
each is for, as clients keep only the start of long instructions."""

from __future__ import annotations

import pytest
from mcp import Client

from bagmcp_gateway.upstreams.instructions import merged_instructions, sentences
from bagmcp_kit.arguments import CONVENTIONS
from tests.fixtures.inprocess import InProcess

SHARED = "Bags: `bag` is an id or a name. Times: numbers below 1e9 are seconds, e.g. 12.5 or ISO-8601."


def test_sentences_end_before_a_capital_or_a_backquote_only() -> None:
    assert sentences(SHARED) == [
        "Bags: `bag` is an id or a name.",
        "Times: numbers below 1e9 are seconds, e.g. 12.5 or ISO-8601.",
    ]
    assert sentences("Paths: e.g. pose.pose.position.x. `bag` first.") == [
        "Paths: e.g. pose.pose.position.x.",
        "`bag` first.",
    ]


def test_shared_sentences_come_once_before_what_each_upstream_is_for() -> None:
    merged = merged_instructions([f"Robot bags. {SHARED}", None, f"Plots. {SHARED}", "Weather readings."])
    assert merged == f"{SHARED} Robot bags. Plots. Weather readings."


def test_no_instructions_anywhere_is_none() -> None:
    assert merged_instructions([None, ""]) is None
    assert merged_instructions(["Only one."]) == "Only one."


@pytest.mark.anyio
@pytest.mark.parametrize("mode", ["auto", "legacy"])  # auto: server/discover at 2026-07-28
async def test_a_client_of_the_in_process_gateway_reads_the_conventions_once(served: InProcess, mode: str) -> None:
    async with Client(served.gateway(), cache=None, mode=mode) as client:
        text = client.instructions
    assert text is not None
    assert text.count(CONVENTIONS) == 1
    assert text.index(CONVENTIONS) < text.index("Plots of robot bags")
