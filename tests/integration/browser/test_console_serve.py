"""The console of `bagmcp serve` (embedded, one process): on loopback without --token it opens straight to
the bags, a bag page draws from the in-process tools, and an upload is refused with the server's reason
(the served folder is read-only)."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest

from tests.fixtures import scenario as sc
from tests.fixtures.bagfactory import BagKind
from tests.fixtures.inprocess import copy_bags
from tests.fixtures.processes import BIN, HTTP, http_ok, service, wait_until
from tests.fixtures.servers import free_port
from tests.integration.browser.harness import Watched, axe_violations, drawn

pytestmark = [pytest.mark.integration, pytest.mark.browser]


@pytest.fixture(scope="module")
def embedded(scenario_bags: dict[BagKind, Path], tmp_path_factory: pytest.TempPathFactory) -> Iterator[str]:
    """`bagmcp serve` on loopback, no token, over a folder with the ROS 1 scenario bag (ingested)."""
    folder = copy_bags([scenario_bags["ros1"]], tmp_path_factory.mktemp("console-bags"))
    port, work = free_port(), tmp_path_factory.mktemp("console-serve")
    command = [str(BIN / "bagmcp"), "serve", "--bags", str(folder), "--port", str(port), "--data", str(work)]
    url = f"http://127.0.0.1:{port}"
    with service("console-serve", command, env={}, log_dir=work, ready=http_ok(f"{url}/healthz")):
        wait_until(
            lambda: HTTP.get(f"{url}/api/v1/bags/scenario").json()["status"] == "ready", timeout_s=60, what="ingest"
        )
        yield url


def test_a_tokenless_local_server_opens_on_its_bags_and_draws_a_bag(embedded: str, watched: Watched) -> None:
    page = watched.page
    page.goto(f"{embedded}/")
    page.wait_for_selector("#bag-list table")
    assert page.locator("#token").count() == 0
    assert page.is_hidden("#signout")
    assert page.is_hidden("#nav-tokens")  # no tokens to manage here
    page.click("#bag-list a:text('scenario')")
    page.click("#tab-trajectory")
    page.wait_for_selector("#panel-trajectory canvas")
    path = [v for v in drawn(page) if v["kind"] == "trajectory"][-1]
    assert len(path["x"]) == sc.COUNTS[sc.ODOM_TOPIC]
    assert axe_violations(page) == []


def test_an_upload_to_a_read_only_folder_is_refused_with_the_reason(
    embedded: str, watched: Watched, tmp_path: Path
) -> None:
    watched.allowed.append("status of 4")  # the refused upload's response, as the browser logs it
    page = watched.page
    page.goto(f"{embedded}/")
    page.wait_for_selector("#upload-file", state="attached")
    bag = tmp_path / "more.bag"
    bag.write_bytes(b"#ROSBAG V2.0\n" + b"\0" * 4096)
    page.set_input_files("#upload-file", str(bag))
    refusal = page.locator("li.upload-item .error")
    refusal.wait_for()
    assert "read-only" in refusal.inner_text()
    assert "uploads are disabled" in refusal.inner_text()
