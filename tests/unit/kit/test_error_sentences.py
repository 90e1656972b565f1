"""Errors quote the caller's arguments; a 10 KB argument is not echoed back whole (over MCP, over HTTP and
in a failed job, all through bagmcp_shared.errors.sentence)."""

from __future__ import annotations

from pathlib import Path

import pytest
from fastapi import FastAPI
from fastapi.testclient import TestClient
from mcp import Client

from bagmcp_kit.http_errors import install_error_handlers
from bagmcp_shared.errors import MAX_SENTENCE_CHARS, ArgumentError, sentence
from tests.fixtures.bagfactory import write_chatter_bag
from tests.fixtures.inprocess import in_process
from tests.fixtures.mcp_client import call_error

pytestmark = pytest.mark.anyio
HUGE = "x" * 10_000


def test_a_long_sentence_keeps_its_start_and_its_end() -> None:
    shown = sentence(ArgumentError(f"bag {HUGE!r} is not here; list_bags shows the bags"))
    assert len(shown) < MAX_SENTENCE_CHARS + 100
    assert shown.startswith("bag 'xxx")
    assert shown.endswith("list_bags shows the bags")
    assert "characters left out" in shown
    assert sentence(ArgumentError("short")) == "short"


async def test_a_10_kb_bag_name_is_not_echoed_whole_by_a_tool(tmp_path: Path) -> None:
    folder = tmp_path / "bags"
    folder.mkdir()
    write_chatter_bag(folder, count=3)
    with in_process(folder, tmp_path / "data") as services:
        async with Client(services.service("bag-store"), cache=None) as client:
            error = await call_error(client, "get_message_at_time", bag=HUGE, topic="/chatter", time=0.0)
    assert len(error) < MAX_SENTENCE_CHARS + 100, len(error)
    assert "characters left out" in error


def test_a_10_kb_argument_is_not_echoed_whole_over_http() -> None:
    app = FastAPI()
    install_error_handlers(app)

    @app.get("/echo")
    def echo(value: str) -> None:
        raise ArgumentError(f"no such thing as {value!r}; try another")

    answer = TestClient(app).get("/echo", params={"value": HUGE})
    message = answer.json()["error"]["message"]
    assert answer.status_code == 400
    assert len(message) < MAX_SENTENCE_CHARS + 100
    assert message.endswith("try another")
