"""bag_info, called as a tool, explains a rate that would mislead: a bag whose messages span 2 µs."""

from __future__ import annotations

import pytest
from mcp import Client

from tests.fixtures import small_bags as small
from tests.fixtures.inprocess import InProcess
from tests.fixtures.mcp_client import call

pytestmark = pytest.mark.anyio


async def test_messages_stamped_within_two_microseconds_come_with_a_note_on_their_rate(
    served_small: InProcess,
) -> None:
    async with Client(served_small.gateway(), cache=None) as client:
        info = await call(client, "bag_info", bag="instant")
    batch = next(t for t in info["topics"] if t["name"] == "/batch")
    rate = (small.INSTANT_COUNT - 1) / (small.INSTANT_SPAN_NS / 1e9)
    assert batch["rate_hz"] == pytest.approx(rate)
    assert batch["note"] == (
        f"all {small.INSTANT_COUNT} messages are stamped within 2.0 µs (written in one batch), "
        f"so the {rate:,.0f} Hz rate says nothing about how often they were published"
    )
