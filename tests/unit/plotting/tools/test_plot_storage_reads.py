"""A plot drawn inline reads storage once (the lookup of its report under the id computed once) and answers
with the PNG bytes it drew, never reading back the image it has just written; a stored plot reads its PNG."""

from __future__ import annotations

import pytest
from mcp import Client

from bagmcp_shared.storage import ObjectStore
from tests.checks.plot_checks import plot
from tests.fixtures.call_spy import first_arguments
from tests.fixtures.inprocess import InProcess

pytestmark = pytest.mark.anyio


@pytest.fixture
def reads(served_drive: InProcess, monkeypatch: pytest.MonkeyPatch) -> list[str]:
    """The object keys read from the services' store while the test runs (the real read still runs)."""
    store: ObjectStore = served_drive.composition.embedded.resources.store
    return first_arguments(monkeypatch, store, "open_read")


async def test_a_fresh_plot_is_looked_up_once_and_its_png_is_not_read_back(
    served_drive: InProcess, reads: list[str]
) -> None:
    arguments = {"bag": "drive_db3", "path": "/imu.angular_velocity.z", "bins": 37}  # asked by no other test
    async with Client(served_drive.service("plotting"), cache=None) as client:
        report, _ = await plot(client, "plot_histogram", **arguments)
        artifact = report["artifact"]["id"]
        assert reads == [f"artifacts/{artifact}.json"]  # the miss before drawing; no second look, no PNG
        reads.clear()
        again, _ = await plot(client, "plot_histogram", **arguments)
    assert again["artifact"]["id"] == artifact
    assert reads == [f"artifacts/{artifact}.json", f"artifacts/{artifact}.png"]  # stored: report, then image
