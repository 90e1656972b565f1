"""The web console in a real browser against the distributed stack: signing in, the bag list following
ingest, uploads (progress, cancel, refusal), tokens, client snippets, phone layout and accessibility."""

from __future__ import annotations

import tarfile
import time
from pathlib import Path
from typing import Any

import httpx
import pytest
from playwright.sync_api import Page

from tests.fixtures.bagfactory import write_chatter_bag
from tests.integration.browser.harness import (
    PHONE,
    Watched,
    axe_violations,
    overflows_horizontally,
    record_dialogs,
    screenshot,
    sign_in,
)
from tests.integration.stack import TOKEN, Stack, bagmcp, new_token

pytestmark = [pytest.mark.integration, pytest.mark.browser]
HOSTILE_NAME = "<img src=x onerror=alert(1)>"


def rows(page: Page) -> dict[str, str]:
    """Bag name -> status text, as the list shows them now."""
    script = (
        "[...document.querySelectorAll('#bag-list tbody tr')].map(r => [r.cells[0].innerText, r.cells[1].innerText])"
    )
    found = page.evaluate(script)
    return {str(name): str(status) for name, status in found}


def test_a_wrong_token_is_refused_and_a_right_one_is_kept_only_in_the_tab(stack: Stack, watched: Watched) -> None:
    page = watched.page
    page.goto(f"{stack.url}/")
    assert "script-src 'self'" in (
        page.evaluate("document.contentType") and httpx.get(f"{stack.url}/").headers["content-security-policy"]
    )
    assert axe_violations(page) == []
    screenshot(page, "console-sign-in")
    watched.allowed.append("401 (Unauthorized)")  # the refused token's request, as the browser logs it
    page.fill("#token", "not-a-token")
    page.click("form button[type=submit]")
    page.wait_for_selector("#signin-message:not(:empty)")
    assert "not valid" in page.inner_text("#signin-message")
    assert page.evaluate("sessionStorage.getItem('bagmcp.token')") is None
    sign_in(page, stack.url, TOKEN)
    assert page.evaluate("sessionStorage.getItem('bagmcp.token')") == TOKEN
    assert page.evaluate("localStorage.length") == 0
    assert TOKEN not in page.url
    assert page.context.cookies() == []
    page.click("#signout")
    page.wait_for_selector("#token")
    assert page.evaluate("sessionStorage.getItem('bagmcp.token')") is None


def test_the_bag_list_follows_a_bag_while_it_ingests(
    stack: Stack, uploaded: dict[str, Any], watched: Watched, tmp_path: Path
) -> None:
    """The bag-store's worker is stopped while the bag is uploaded, so its ingest waits (a fast machine
    would otherwise finish it between two refreshes); the list shows it ingesting, then ready."""
    page = watched.page
    sign_in(page, stack.url, TOKEN)
    assert {str(b["name"]) for b in uploaded.values()} <= set(rows(page))
    archive = _tarred(write_chatter_bag(tmp_path, count=50_001, name="web_ingest"))
    stack.kill_worker(stack.latest_worker("bag-store"))
    try:
        answer = stack.rest("POST", "bags", params={"filename": archive.name}, content=archive.read_bytes())
        assert answer.status_code == 201, answer.text
        page.wait_for_function("() => document.querySelector('#bag-list').innerText.includes('web_ingest')")
        assert rows(page)["web_ingest"].startswith("ingesting")
        screenshot(page, "console-bags")
        assert axe_violations(page) == []
    finally:
        stack.start_worker("bag-store")
    seen = [rows(page)["web_ingest"]]
    deadline = time.monotonic() + 120
    while seen[-1] != "ready" and time.monotonic() < deadline:
        time.sleep(0.2)
        if (status := rows(page)["web_ingest"]) != seen[-1]:
            seen.append(status)
    assert seen[-1] == "ready", seen
    assert page.locator("#bag-list tr", has_text="web_ingest").locator("a").get_attribute("href") == (
        f"#/bag/{stack.bags()['web_ingest']['id']}"
    )


def _throttle(page: Page, *, bytes_per_s: int) -> None:
    cdp = page.context.new_cdp_session(page)
    cdp.send("Network.enable")
    conditions = {"offline": False, "latency": 0, "downloadThroughput": -1, "uploadThroughput": bytes_per_s}
    cdp.send("Network.emulateNetworkConditions", conditions)


def _tarred(bag: Path) -> Path:
    """A ROS 2 bag directory as the tar archive an upload takes."""
    archive = bag.with_name(f"{bag.name}.tar")
    with tarfile.open(archive, "w") as tar:
        tar.add(bag, arcname=bag.name)
    return archive


def test_an_upload_shows_its_progress_can_be_cancelled_and_a_refusal_says_why(
    stack: Stack, watched: Watched, tmp_path: Path
) -> None:
    page = watched.page
    sign_in(page, stack.url, TOKEN)
    archive = _tarred(write_chatter_bag(tmp_path, count=60_000, name="web_upload"))
    size = archive.stat().st_size
    _throttle(page, bytes_per_s=max(size // 4, 200_000))  # about four seconds on the wire
    page.set_input_files("#upload-file", str(archive))
    item = page.locator("li.upload-item", has_text="web_upload.tar")
    fractions: list[float] = []
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline and not item.locator(".ok").count():
        fractions.append(float(item.locator("progress").evaluate("p => p.value")))
        time.sleep(0.1)
    assert any(0.05 < f < 0.95 for f in fractions), fractions  # seen part-way, not only at the end
    assert "stored as web_upload" in item.inner_text()
    page.wait_for_function(
        "() => [...document.querySelectorAll('#bag-list td')].some(td => td.innerText === 'web_upload')"
    )

    watched.allowed.append("400 (Bad Request)")
    watched.allowed.append("422 (Unprocessable")
    junk = tmp_path / f"{HOSTILE_NAME}.bag"
    junk.write_bytes(b"this is not a bag at all\n" * 200)
    dialogs = record_dialogs(page)
    page.set_input_files("#upload-file", str(junk))
    refused = page.locator("li.upload-item", has_text=HOSTILE_NAME)
    refused.locator(".error").wait_for()
    assert refused.locator(".error").inner_text().startswith("refused: ")
    assert len(refused.locator(".error").inner_text()) > len("refused: ") + 10
    assert page.locator("img[src=x]").count() == 0
    assert dialogs == []
    screenshot(page, "console-upload")

    big_archive = _tarred(write_chatter_bag(tmp_path, count=120_000, name="web_cancel"))
    _throttle(page, bytes_per_s=max(big_archive.stat().st_size // 10, 100_000))
    page.set_input_files("#upload-file", str(big_archive))
    cancelled = page.locator("li.upload-item", has_text="web_cancel.tar")
    cancelled.locator("progress").wait_for()
    page.wait_for_function("el => el.value > 0.05", arg=cancelled.locator("progress").element_handle())
    cancelled.get_by_role("button", name="Cancel").click()
    cancelled.locator(".error", has_text="cancelled").wait_for()
    time.sleep(2)
    assert "web_cancel" not in stack.bags()


def test_deleting_a_bag_needs_the_delete_scope_and_removes_its_row(
    stack: Stack, watched: Watched, tmp_path: Path
) -> None:
    archive = _tarred(write_chatter_bag(tmp_path, count=1_003, name="web_delete"))
    answer = stack.rest("POST", "bags", params={"filename": archive.name}, content=archive.read_bytes())
    assert answer.status_code == 201, answer.text
    page = watched.page
    page.on("dialog", lambda d: d.accept())
    watched.allowed.append("403 (Forbidden)")  # the refused delete, as the browser logs it
    sign_in(page, stack.url, new_token(stack, "web-reader", "--scopes", "read"))
    assert page.is_hidden("#nav-tokens")  # not an admin
    page.locator("#bag-list tr", has_text="web_delete").get_by_role("button", name="Delete").click()
    page.wait_for_selector("#toast:has-text('delete scope')")
    assert "web_delete" in stack.bags()
    page.click("#signout")
    sign_in(page, stack.url, TOKEN)
    page.locator("#bag-list tr", has_text="web_delete").get_by_role("button", name="Delete").click()
    page.locator("#bag-list tr", has_text="web_delete").wait_for(state="detached")
    assert "web_delete" not in stack.bags()


def test_an_admin_creates_a_token_that_works_and_revokes_it(stack: Stack, watched: Watched) -> None:
    page = watched.page
    sign_in(page, stack.url, TOKEN)
    page.click("#nav-tokens")
    page.fill("#token-name", "web-console-made")
    page.check("#scope-upload")
    page.select_option("#token-profile", "core")
    page.fill("#token-expires", "1d")
    page.click("form button[type=submit]")
    secret = page.locator("#new-secret").input_value()
    assert len(secret) > 20
    listed = page.locator("#token-list tr", has_text="web-console-made")
    assert "read, upload" in listed.inner_text()
    assert "core" in listed.inner_text()
    headers = {"Authorization": f"Bearer {secret}"}
    assert httpx.get(f"{stack.url}/api/v1/bags", headers=headers).status_code == 200
    assert axe_violations(page) == []
    screenshot(page, "console-tokens")
    page.on("dialog", lambda d: d.accept())
    listed.get_by_role("button", name="Revoke").click()
    page.locator("#token-list tr", has_text="web-console-made").wait_for(state="detached")
    assert httpx.get(f"{stack.url}/api/v1/bags", headers=headers).status_code == 401


@pytest.mark.parametrize("client", ["claude-code", "cursor", "desktop"])
def test_the_client_snippets_are_the_ones_the_cli_prints(stack: Stack, watched: Watched, client: str) -> None:
    page = watched.page
    sign_in(page, stack.url, TOKEN)
    page.goto(f"{stack.url}/#/clients")
    shown = page.inner_text(f"#snippet-{client}")
    printed = bagmcp("config", "--client", client, "--url", f"{stack.url}/mcp", "--token", "YOUR_TOKEN")
    assert printed.returncode == 0, printed.stderr
    assert shown.strip() == printed.stdout.strip()
    if client == "desktop":
        assert axe_violations(page) == []
        screenshot(page, "console-clients")


def test_on_a_phone_the_pages_fit_the_screen(stack: Stack, uploaded: dict[str, Any], watched: Watched) -> None:
    page = watched.page
    page.set_viewport_size(PHONE)
    sign_in(page, stack.url, TOKEN)
    assert not overflows_horizontally(page)
    screenshot(page, "console-phone-bags")
    page.goto(f"{stack.url}/#/bag/{uploaded['ros1']['name']}")
    page.click("#tab-trajectory")
    page.wait_for_selector("#panel-trajectory canvas")
    assert not overflows_horizontally(page)
    screenshot(page, "console-phone-trajectory")
