"""Answers across the real recordings (../shared/data/bags, every readable format) agree with the per-bag
tools in both ways of running: the embedded server over the corpus folder, and the distributed stack (real
weed S3, Redis and Celery workers) with every bag the embedded server lists as ready uploaded to it. The
checks are tests/checks/fleet_corpus_checks.py's, the same for both."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest
from mcp import Client

from tests.checks.fleet_corpus_checks import check_corpus
from tests.fixtures.inprocess import InProcess, in_process
from tests.fixtures.mcp_client import http_client, ingested_bags
from tests.integration.stack import TOKEN, Stack

pytestmark = [pytest.mark.anyio, pytest.mark.corpus]


@pytest.fixture(scope="module")
def served(corpus: Path, tmp_path_factory: pytest.TempPathFactory) -> Iterator[InProcess]:
    """The embedded server over the corpus, every bag ingested (about 40 s on a shared 2-core machine)."""
    with in_process(corpus, tmp_path_factory.mktemp("fleet-corpus"), timeout_s=300) as services:
        yield services


def _ready(served: InProcess, corpus: Path) -> dict[str, Path]:
    """The bags the embedded server has ready, by name, with their file or ROS 2 directory in the corpus."""
    records = served.composition.embedded.resources.catalog.all()
    return {r.name: corpus / r.source for r in records if r.status == "ready"}


async def test_answers_across_the_corpus_agree_with_the_per_bag_tools(served: InProcess, corpus: Path) -> None:
    async with Client(served.gateway(), cache=None) as client:
        names = [b["name"] for b in await ingested_bags(client) if b["status"] == "ready"]
        assert sorted(names) == sorted(_ready(served, corpus))
        assert len(names) >= 10
        await check_corpus(client, names)


async def test_the_stack_answers_across_the_uploaded_corpus_like_the_per_bag_tools(
    stack: Stack, served: InProcess, corpus: Path
) -> None:
    # a bag another test uploaded already (same content) answers under the name it has there
    names = [str(stack.upload_ok(path, name=name)["name"]) for name, path in _ready(served, corpus).items()]
    await stack.wait_ready(names, timeout_s=300)
    async with http_client(f"{stack.url}/mcp", TOKEN) as client:
        await check_corpus(client, names)
