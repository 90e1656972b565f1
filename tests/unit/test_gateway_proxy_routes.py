"""The gateway forwards only the bag-store's REST routes, never a path that could reach another endpoint."""

from __future__ import annotations

import pytest

from bagmcp_gateway.proxy import forwardable


@pytest.mark.parametrize(
    "path", ["bags", "bags/scenario", "bags/a8fbb0c0/download", "bags/run_2024-01-01.v2", "bags/run..1"]
)
def test_bag_routes_are_forwarded(path: str) -> None:
    assert forwardable(path)


@pytest.mark.parametrize(
    "path",
    [
        "../mcp",
        "..%2F..%2Fmcp",
        "bags/../../mcp",
        "bags/..",
        "mcp",
        "bags/x/download/more",
        "healthz",
        "bags/x/../y",
        "bags/.hidden",
        "bags//download",
    ],
)
def test_anything_else_is_refused(path: str) -> None:
    assert not forwardable(path)
