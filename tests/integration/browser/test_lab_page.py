"""The Lab page in a real browser over `bagmcp serve` (with a token) and the scripted model server: a chat turn
whose tool step shows its plot, a benchmark run filling its table and figures, and the model key kept out of
every URL, cookie, local storage and the server's log (it travels only in the bodies of Lab requests)."""

from __future__ import annotations

import json
import time
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path

import pytest
from playwright.sync_api import Page, Request

from tests.fixtures.drive_bags import write_drive_bag
from tests.fixtures.lab_runs import served_folder
from tests.fixtures.scripted_model import ScriptedModel, scripted_model_server
from tests.integration.browser.harness import Watched, axe_violations, screenshot

pytestmark = [pytest.mark.integration, pytest.mark.browser]
TOKEN = "lab-page-token"
KEY = "sk-lab-page-test-7d41"
PROMPT = "Plot linear and angular velocity from t=10 s to t=30 s. (bag: drive)"


@dataclass(frozen=True)
class Served:
    url: str
    log: Path


@dataclass
class Sent:
    """Every request the page made: its URL, and whether its body held the key."""

    urls: list[str] = field(default_factory=list)
    keyed: list[str] = field(default_factory=list)

    def record(self, request: Request) -> None:
        self.urls.append(request.url)
        if KEY in (request.post_data or ""):
            self.keyed.append(request.url)


@pytest.fixture(scope="module")
def model() -> Iterator[ScriptedModel]:
    with scripted_model_server(KEY) as scripted:
        yield scripted


@pytest.fixture(scope="module")
def served(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Served]:
    folder = tmp_path_factory.mktemp("lab-page-bags")
    write_drive_bag("ros1", folder)
    with served_folder(folder, tmp_path_factory.mktemp("lab-page"), name="lab-page", token=TOKEN) as (url, log):
        yield Served(url, log)


def _choose_model(page: Page, served: Served, model: ScriptedModel) -> None:
    page.goto(f"{served.url}/lab")
    page.fill("#lab-token", TOKEN)
    page.select_option("#lab-provider", "openai")
    page.fill("#lab-model", "capable")
    page.fill("#lab-base-url", model.openai_url)
    page.fill("#lab-key", KEY)


def test_a_chat_turn_shows_the_tool_step_with_its_plot(served: Served, model: ScriptedModel, watched: Watched) -> None:
    page, sent = watched.page, Sent()
    page.on("request", sent.record)
    _choose_model(page, served, model)
    assert axe_violations(page) == []
    page.fill("#chat-input", PROMPT)
    page.click("#chat-send")
    page.wait_for_selector(".lab-meta")
    step = page.locator(".lab-step")
    assert step.count() == 1
    assert step.locator("strong").inner_text() == "plot_timeseries"
    assert '"start": 10' in step.locator(".lab-args").inner_text()
    assert step.locator(".lab-step-state").inner_text().endswith(" ms")
    image = step.locator("img.lab-image")
    assert page.evaluate("(img) => img.naturalWidth", image.element_handle()) > 300
    assert "/cmd_vel.linear.x from 0 to 0.5" in page.locator(".lab-reply").inner_text()
    assert page.locator(".lab-meta").inner_text().startswith("1 tool calls · ")
    screenshot(page, "lab-chat")
    _assert_key_kept(page, served, sent, posted_to=[f"{served.url}/api/v1/lab/chat"])


def test_a_benchmark_run_fills_its_table_and_figures(served: Served, model: ScriptedModel, watched: Watched) -> None:
    page, sent = watched.page, Sent()
    page.on("request", sent.record)
    _choose_model(page, served, model)
    page.click("#tab-bench")
    page.wait_for_selector("#bench-bag option[value=drive]", state="attached")
    page.click("#bench-start")
    page.locator("#bench-status", has_text="Finished").wait_for(timeout=180_000)
    assert page.inner_text("#bench-status") == "Finished (succeeded): 10 of 10 runs done, 10 succeeded"
    cells = page.locator("#bench-results tbody tr td:nth-child(3)").all_inner_texts()
    assert len(cells) == 10
    assert all(cell.startswith("✓ ") for cell in cells), cells
    assert cells[2] == "✓ analyze_trajectory"
    loaded = "() => [...document.querySelectorAll('.lab-figure')].filter(i => i.complete && i.naturalWidth > 0).length"
    deadline = time.monotonic() + 30
    while page.evaluate(loaded) < 2:  # (wait_for_function evaluates strings, which the page's CSP forbids)
        assert time.monotonic() < deadline, "the figures did not load"
        page.wait_for_timeout(200)
    with page.expect_download() as download:
        page.click("#bench-download")
    runs = json.loads(Path(download.value.path()).read_text())
    assert [run["success"] for run in runs] == [True] * 10
    screenshot(page, "lab-benchmark")
    _assert_key_kept(page, served, sent, posted_to=[f"{served.url}/api/v1/lab/runs"])


def _assert_key_kept(page: Page, served: Served, sent: Sent, *, posted_to: list[str]) -> None:
    assert sent.keyed == posted_to  # only in the body of the Lab's own request
    assert not [url for url in [page.url, *sent.urls] if KEY in url]
    assert page.evaluate("localStorage.length") == 0
    assert page.context.cookies() == []
    assert page.evaluate("sessionStorage.getItem('bagmcp.lab.key')") == KEY  # this tab only
    assert KEY not in served.log.read_text()
