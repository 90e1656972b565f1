"""A bag's page in the console: every view drawn from the stack's tools and checked against the scenario
bag's known values, log texts that are markup shown as text, and a job followed on the Jobs page."""

from __future__ import annotations

import time
from pathlib import Path
from typing import Any

import pytest
from playwright.sync_api import Page

from tests.fixtures import scenario as sc
from tests.integration.browser.apps_client import call_tool
from tests.integration.browser.harness import Watched, axe_violations, drawn, record_dialogs, screenshot, sign_in
from tests.integration.browser.hostile_bags import IMG_NODE, IMG_TOPIC, SCRIPT_TEXT, write_hostile_log_bag
from tests.integration.stack import TOKEN, Stack

pytestmark = [pytest.mark.integration, pytest.mark.browser]
HOSTILE_TAG = "<img src=x onerror=alert(2)>"


def _open(page: Page, stack: Stack, bag: str, tab: str, ready: str) -> None:
    page.goto(f"{stack.url}/#/bag/{bag}")
    page.click(f"#tab-{tab}")
    page.wait_for_selector(f"#panel-{tab} {ready}")


def _last(page: Page, kind: str) -> dict[str, Any]:
    return [v for v in drawn(page) if v["kind"] == kind][-1]


def test_a_bag_page_shows_each_view_with_the_bag_s_numbers(
    stack: Stack, uploaded: dict[str, Any], watched: Watched
) -> None:
    page, bag = watched.page, str(uploaded["ros1"]["name"])
    sign_in(page, stack.url, TOKEN)
    page.goto(f"{stack.url}/#/bag/{bag}")
    topics = page.locator("#panel-topics tbody tr")
    topics.first.wait_for()
    script = "[...document.querySelectorAll('#panel-topics tbody tr')].map(r => [r.cells[0].innerText, +r.cells[2].innerText])"  # noqa: E501
    assert dict(page.evaluate(script)) == sc.COUNTS
    assert axe_violations(page) == []
    screenshot(page, "console-bag-topics")

    page.click("#tab-plot")
    page.select_option("#plot-topic", sc.CMD_TOPIC)
    page.wait_for_selector("#plot-field option[value='linear.x']", state="attached")
    page.select_option("#plot-field", "linear.x")
    page.click("#panel-plot button.primary")
    page.wait_for_function(
        "() => (BagViews.drawn || []).some(v => v.kind === 'timeseries' && v.names[0] === '/cmd_vel.linear.x')"
    )
    series = _last(page, "timeseries")
    assert len(series["data"][0]) == sc.COUNTS[sc.CMD_TOPIC]
    assert all(v == pytest.approx(sc.cmd_speed_at(t)) for t, v in zip(*series["data"], strict=True))
    assert axe_violations(page) == []
    screenshot(page, "console-bag-plot")

    page.click("#tab-trajectory")
    page.wait_for_selector("#panel-trajectory canvas")
    path = _last(page, "trajectory")
    assert path["x"][-1] == pytest.approx(sc.pose_at(path["t"][-1])[0], abs=1e-4)
    assert "Distance" in page.inner_text("#panel-trajectory")
    screenshot(page, "console-bag-trajectory")

    page.click("#tab-scan")
    page.wait_for_selector("#panel-scan canvas")
    page.locator("#panel-scan input[type=range]").fill("0")
    assert min(p["r"] for p in _last(page, "scan")["points"]) == pytest.approx(sc.FREE_RANGE_M)
    screenshot(page, "console-bag-scan")

    page.click("#tab-logs")
    page.wait_for_selector("#panel-logs .logline")
    assert page.locator("#panel-logs .logline").count() == len(sc.LOGS)
    page.uncheck("#level-INFO")
    shown = page.locator("#panel-logs .logline").all_inner_texts()
    assert [line.split("] ")[0].split("[")[1] for line in shown] == ["WARN", "ERROR"]
    assert axe_violations(page) == []
    screenshot(page, "console-bag-logs")

    page.click("#tab-tf")
    page.wait_for_selector("#tf-tree li")
    assert {"odom", "base_link"} <= {
        t.split(" (")[0] for t in page.locator("#tf-tree li").all_inner_texts() for t in t.splitlines()
    }
    screenshot(page, "console-bag-tf")

    page.click("#tab-image")
    page.select_option("#image-topic", sc.IMAGE_TOPIC)
    picture = page.locator("#image-out img")
    picture.wait_for()
    page.wait_for_function("img => img.complete && img.naturalWidth > 0", arg=picture.element_handle())
    assert picture.evaluate("img => img.naturalWidth") == 4
    assert axe_violations(page) == []
    screenshot(page, "console-bag-image")


def test_log_texts_tags_and_topic_names_that_are_markup_show_as_text(
    stack: Stack, watched: Watched, tmp_path: Path
) -> None:
    page = watched.page
    dialogs = record_dialogs(page)
    bag = write_hostile_log_bag(tmp_path)
    answer = stack.rest("POST", "bags", params={"filename": bag.name, "tags": [HOSTILE_TAG]}, content=bag.read_bytes())
    assert answer.status_code in (200, 201), answer.text
    name = answer.json()["bag"]["name"]
    deadline = time.monotonic() + 60
    while stack.bags()[name]["status"] != "ready" and time.monotonic() < deadline:
        time.sleep(0.3)
    sign_in(page, stack.url, TOKEN)
    page.goto(f"{stack.url}/#/bag/{name}")
    page.locator("#panel-topics tbody tr").first.wait_for()
    topics = page.locator("#panel-topics tbody tr td:first-child").all_inner_texts()
    assert sorted(topics) == sorted([sc.LOG_TOPIC, IMG_TOPIC])
    _open(page, stack, name, "logs", ".logline")
    lines = page.locator("#panel-logs .logline").all_inner_texts()
    assert sum(SCRIPT_TEXT in line and IMG_NODE in line for line in lines) == 2
    assert HOSTILE_TAG in page.inner_text("dl.facts")
    assert page.locator("img[src=x], #panel-logs script").count() == 0
    time.sleep(0.5)  # an injected onerror would have fired by now
    assert dialogs == []


def test_a_job_is_followed_from_queued_to_its_end(stack: Stack, uploaded: dict[str, Any], watched: Watched) -> None:
    """filter_bag always runs as a job on the bag-store queue; with that queue's worker stopped it stays
    queued, and the Jobs page shows it so, then succeeded once a worker is back."""
    page = watched.page
    sign_in(page, stack.url, TOKEN)
    stack.kill_worker(stack.latest_worker("bag-store"))
    try:
        arguments = {"bag": str(uploaded["ros1"]["name"]), "name": "web_job", "include_topics": ["/odom"]}
        job = call_tool(stack.url, TOKEN, "filter_bag", arguments)["structuredContent"]["job"]
        page.click("nav a[href='#/jobs']")
        page.fill("#job-id", job["job_id"])
        page.click("#main form button[type=submit]")
        row = page.locator("#job-list tr", has_text=job["job_id"])
        row.filter(has_text="queued").wait_for()
        assert "0%" in row.inner_text()
    finally:
        stack.start_worker("bag-store")
    row.filter(has_text="succeeded").wait_for(timeout=120_000)
    assert "100%" in row.inner_text()
    assert axe_violations(page) == []
    screenshot(page, "console-jobs")
