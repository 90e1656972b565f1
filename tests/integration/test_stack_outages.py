"""The object store stops answering: clear errors, the catalog and cached bags keep working, and
everything recovers when it answers again, without restarting any service (DESIGN section 8)."""

from __future__ import annotations

import os
import signal
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import httpx
import pytest

from tests.fixtures.bagfactory import BagKind, write_chatter_bag
from tests.fixtures.mcp_client import call, http_client
from tests.integration.stack import TOKEN, Stack

pytestmark = pytest.mark.anyio


@contextmanager
def frozen(pid: int) -> Iterator[None]:
    """The S3 server process stopped (SIGSTOP): it accepts connections but never answers."""
    os.kill(pid, signal.SIGSTOP)
    try:
        yield
    finally:
        os.kill(pid, signal.SIGCONT)


async def test_an_unanswering_object_store_gives_clear_errors_and_recovers_without_restarts(
    stack: Stack, uploaded: dict[BagKind, dict[str, Any]], tmp_path: Path
) -> None:
    if not stack.s3.pid:
        pytest.skip("the S3 server runs in a container; this test pauses a local process")
    new_bag = write_chatter_bag(tmp_path, count=100, name="after_outage")
    async with http_client(f"{stack.url}/mcp", TOKEN) as client:
        await call(client, "get_message_at_time", bag="scenario_mcap", topic="/odom", time=1.0)  # now cached
        with frozen(stack.s3.pid):
            began = time.monotonic()
            refused = stack.upload(new_bag)
            assert time.monotonic() - began < 30
            assert refused.returncode == 1
            assert "503" in refused.stderr
            assert "object store" in refused.stderr
            listing = await call(client, "list_bags", name="scenario")
            assert listing["total"] >= 3
            info = await call(client, "bag_info", bag="scenario_mcap")
            assert info["message_count"] == 595
            cached = await call(client, "get_message_at_time", bag="scenario_mcap", topic="/odom", time=2.0)
            assert cached["message"]["time"]["offset_s"] == pytest.approx(2.0)
            assert (await call(client, "list_bags", name="after_outage"))["total"] == 0
        answer = stack.upload_ok(new_bag)
        assert answer["name"] == "after_outage"
    headers = {"Authorization": f"Bearer {TOKEN}"}
    assert httpx.get(f"{stack.url}/api/v1/bags/after_outage", headers=headers).status_code == 200
