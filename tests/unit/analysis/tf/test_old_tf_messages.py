"""ROS 1 bags from before tf2 carry transforms as ``tf/tfMessage``: the tree and lookups read them the same."""

from __future__ import annotations

import pytest
from mcp import Client

from tests.checks.analysis_checks import check_tf
from tests.fixtures.inprocess import InProcess
from tests.fixtures.mcp_client import call

pytestmark = pytest.mark.anyio


async def test_the_tree_and_lookups_of_old_tf_messages_match_the_drive(served_small: InProcess) -> None:
    async with Client(served_small.gateway(), cache=None) as client:
        info = await call(client, "bag_info", bag="old_tf")
        assert {t["type"] for t in info["topics"]} == {"tf/msg/tfMessage"}
        await check_tf(client, "old_tf")
