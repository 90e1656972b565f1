"""Every plotting tool on the drive bags in three formats, through the in-process gateway."""

from __future__ import annotations

import pytest
from mcp import Client

from tests.checks.plot_checks import check_plots
from tests.fixtures.inprocess import InProcess
from tests.unit.conftest import DRIVE_NAMES

pytestmark = pytest.mark.anyio


@pytest.mark.parametrize("bag", DRIVE_NAMES)
async def test_every_plot_is_a_real_image_with_a_summary_that_matches_the_drive(
    served_drive: InProcess, bag: str
) -> None:
    other = next(b for b in DRIVE_NAMES if b != bag)
    async with Client(served_drive.gateway(), cache=None) as client:
        await check_plots(client, bag, other)
