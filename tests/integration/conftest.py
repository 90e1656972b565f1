"""Session-wide distributed stack shared by the integration tests that need one."""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import ExitStack
from pathlib import Path
from typing import Any

import anyio
import pytest

from tests.fixtures.bagfactory import BagKind, write_chatter_bag, write_transform_bag
from tests.fixtures.processes import HTTP, wait_until
from tests.fixtures.servers import S3Endpoint
from tests.integration.stack import TOKEN, Stack, start_stack

SCENARIO_NAMES = ["scenario", "scenario_db3", "scenario_mcap"]
CHATTER_MESSAGES = 300_000
POSES_TF_MESSAGES = 300_000


@pytest.fixture(scope="session")
def stack(redis_url: str, s3_server: S3Endpoint, tmp_path_factory: pytest.TempPathFactory) -> Iterator[Stack]:
    with ExitStack() as exits:
        yield start_stack(redis_url, s3_server, tmp_path_factory.mktemp("stack"), exits)


@pytest.fixture(scope="session")
def uploaded(stack: Stack, scenario_bags: dict[BagKind, Path]) -> dict[BagKind, dict[str, Any]]:
    """The three scenario bags uploaded with `bagmcp upload` (ids and names)."""
    answers = {kind: stack.upload_ok(path) for kind, path in scenario_bags.items()}
    wait_until(lambda: _all_ready(stack), timeout_s=120, what="the uploaded bags to be ingested")
    return answers


@pytest.fixture(scope="session")
def chatter(stack: Stack, tmp_path_factory: pytest.TempPathFactory) -> str:
    """A 300,000-message bag uploaded to the stack: searching or scanning it outlasts the job budget."""
    answer = stack.upload_ok(write_chatter_bag(tmp_path_factory.mktemp("chatter"), count=CHATTER_MESSAGES))
    anyio.run(stack.wait_ready, [answer["name"]])
    return str(answer["name"])


@pytest.fixture(scope="session")
def poses_tf(stack: Stack, tmp_path_factory: pytest.TempPathFactory) -> str:
    """300,000 TransformStamped (not in the columnar index): analysing them outlasts the job budget."""
    answer = stack.upload_ok(write_transform_bag(tmp_path_factory.mktemp("poses"), count=POSES_TF_MESSAGES))
    anyio.run(stack.wait_ready, [answer["name"]])
    return str(answer["name"])


def _all_ready(stack: Stack) -> bool:
    listing = HTTP.get(f"{stack.url}/api/v1/bags", params={"limit": 500}, headers={"Authorization": f"Bearer {TOKEN}"})
    return all(b["status"] != "ingesting" for b in listing.json()["bags"])


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    """Everything under tests/integration starts real servers or processes: mark it ``integration``."""
    here = Path(__file__).parent
    for item in items:
        if here in Path(str(item.path)).parents:
            item.add_marker(pytest.mark.integration)
