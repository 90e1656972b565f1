"""Driving Debian's Chromium with Playwright for the browser tests: the launch flags, a page that records
every console error and page error (a test fails on any), the accessibility check with axe-core, and
screenshots for the README.

Chromium comes from the distribution (`make browser` installs the ``chromium`` package when missing);
nothing is downloaded at test time, and a missing browser fails the tests rather than skipping them."""

from __future__ import annotations

import json
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from playwright.sync_api import ConsoleMessage, Dialog, Error, Frame, Page, ViewportSize

ROOT = Path(__file__).resolve().parents[3]
CHROMIUM = Path(os.environ.get("BAGMCP_CHROMIUM", "/usr/bin/chromium"))
FLAGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
]
AXE = ROOT / "node_modules" / "axe-core" / "axe.min.js"
SHOTS = ROOT / "docs" / "images" / "web"
LAPTOP: ViewportSize = {"width": 1280, "height": 860}
PHONE: ViewportSize = {"width": 390, "height": 844}


def chromium_or_fail() -> str:
    """The browser's path; a clear failure (not a skip) when the package is missing."""
    if not CHROMIUM.is_file():
        raise RuntimeError(f"no Chromium at {CHROMIUM}: run `make browser` (apt-get install chromium) first")
    return str(CHROMIUM)


@dataclass
class Watched:
    """A page and what went wrong in it: console errors and uncaught exceptions."""

    page: Page
    errors: list[str] = field(default_factory=list)
    allowed: list[str] = field(default_factory=list)  # substrings of errors a test provokes on purpose

    def __post_init__(self) -> None:
        self.page.on("console", self._console)
        self.page.on("pageerror", self._page_error)

    def _console(self, message: ConsoleMessage) -> None:
        if message.type == "error":
            self.errors.append(f"console: {message.text} ({message.location.get('url', '')})")

    def _page_error(self, error: Error) -> None:
        self.errors.append(f"page error: {error.message}")

    def unexpected(self) -> list[str]:
        return [e for e in self.errors if not any(a in e for a in self.allowed)]


def axe_violations(target: Page | Frame) -> list[dict[str, Any]]:
    """axe-core's serious and critical findings on a page or in a frame (an Apps viewer's iframe)."""
    # evaluated through the debugging protocol, which the page's CSP does not govern (a script tag would be
    # refused by it, as the tests want for everything else)
    target.evaluate(AXE.read_text(encoding="utf-8") + "\n;true")
    found = target.evaluate("async () => (await axe.run(document, {resultTypes: ['violations']})).violations")
    return [
        {"id": v["id"], "impact": v["impact"], "nodes": [n["target"] for n in v["nodes"]][:5]}
        for v in found
        if v["impact"] in ("serious", "critical")
    ]


def screenshot(page: Page, name: str) -> Path | None:
    """Save a screenshot for the README when BAGMCP_SCREENSHOTS=1 (docs/images/web/<name>.png)."""
    if os.environ.get("BAGMCP_SCREENSHOTS") != "1":
        return None
    SHOTS.mkdir(parents=True, exist_ok=True)
    path = SHOTS / f"{name}.png"
    page.screenshot(path=str(path), full_page=True)
    return path


def drawn(page_or_frame: Any) -> list[dict[str, Any]]:
    """What the shared views drew (``BagViews.drawn``), as plain JSON."""
    return list(json.loads(page_or_frame.evaluate("JSON.stringify(window.BagViews.drawn || [])")))


def sign_in(page: Page, url: str, token: str) -> None:
    """Open the console at ``url`` and sign in with ``token`` (the bag list shows once it is accepted)."""
    page.goto(f"{url}/")
    page.fill("#token", token)
    page.click("form button[type=submit]")
    page.wait_for_selector("#bag-list table")


def overflows_horizontally(page: Page) -> bool:
    """Whether the page is wider than the window (a phone would scroll sideways)."""
    return bool(page.evaluate("document.documentElement.scrollWidth > window.innerWidth + 1"))


def record_dialogs(page: Page) -> list[str]:
    """The messages of every alert/confirm the page opens from now on (each dismissed): script injected
    through a name or a log line would open one."""
    seen: list[str] = []

    def dismiss(dialog: Dialog) -> None:
        seen.append(dialog.message)
        dialog.dismiss()

    page.on("dialog", dismiss)
    return seen
