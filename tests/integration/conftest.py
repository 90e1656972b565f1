"""Session-wide distributed stack shared by the integration tests that need one."""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import ExitStack
from pathlib import Path
from typing import Any

import httpx
import pytest

from tests.fixtures.bagfactory import BagKind
from tests.fixtures.processes import wait_until
from tests.fixtures.servers import S3Endpoint
from tests.integration.stack import TOKEN, Stack, start_stack

SCENARIO_NAMES = ["scenario", "scenario_db3", "scenario_mcap"]


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


def _all_ready(stack: Stack) -> bool:
    listing = httpx.get(f"{stack.url}/api/v1/bags", params={"limit": 500}, headers={"Authorization": f"Bearer {TOKEN}"})
    return all(b["status"] != "ingesting" for b in listing.json()["bags"])
