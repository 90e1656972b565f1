"""Fixtures of the browser tests: a Playwright driver and a fresh Chromium profile per module, and per test a
watched page that fails the test on any browser console error.

The driver lives only as long as a module: Playwright's sync API runs an event loop in the test thread while
it is started, and the async tests that pytest runs after these modules need that thread's loop free."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest
from playwright.sync_api import BrowserContext, Playwright, sync_playwright

from tests.integration.browser.harness import FLAGS, LAPTOP, Watched, chromium_or_fail


@pytest.fixture(scope="module")
def driver() -> Iterator[Playwright]:
    with sync_playwright() as playwright:
        yield playwright


@pytest.fixture(scope="module")
def browser(driver: Playwright, tmp_path_factory: pytest.TempPathFactory) -> Iterator[BrowserContext]:
    profile: Path = tmp_path_factory.mktemp("chromium-profile")
    context = driver.chromium.launch_persistent_context(
        str(profile), executable_path=chromium_or_fail(), args=FLAGS, headless=True, viewport=LAPTOP
    )
    context.set_default_timeout(20_000)
    yield context
    context.close()


@pytest.fixture
def watched(browser: BrowserContext) -> Iterator[Watched]:
    page = browser.new_page()
    watch = Watched(page)
    yield watch
    page.close()
    assert watch.unexpected() == []
