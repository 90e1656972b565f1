"""The gateway forwards only configured REST routes, never a path that could reach another endpoint."""

from __future__ import annotations

import pytest

from bagmcp_gateway.rest_front.proxy import forwarded_headers, route_of

ROUTES = {"bags": "http://bag-store:8001", "artifacts": "http://plotting:8003"}


@pytest.mark.parametrize(
    ("path", "base"),
    [
        ("bags", "http://bag-store:8001"),
        ("bags/scenario", "http://bag-store:8001"),
        ("bags/a8fbb0c0/download", "http://bag-store:8001"),
        ("bags/run_2024-01-01.v2", "http://bag-store:8001"),
        ("bags/run..1", "http://bag-store:8001"),
        ("artifacts/4f2a9c", "http://plotting:8003"),
    ],
)
def test_configured_routes_are_forwarded_to_their_service(path: str, base: str) -> None:
    assert route_of(path, ROUTES) == base


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
        "tokens",
    ],
)
def test_anything_else_is_refused(path: str) -> None:
    assert route_of(path, ROUTES) is None


def test_only_the_lab_gets_the_callers_token_and_no_client_can_forge_it() -> None:
    sent = {"Authorization": "Bearer caller-token", "X-Bagmcp-Caller": "Bearer forged", "Accept": "application/json"}
    to_lab = forwarded_headers(sent, "lab/runs", service_token="service", caller_segments=("lab",))
    assert to_lab == {
        "Accept": "application/json",
        "authorization": "Bearer service",
        "x-bagmcp-caller": "Bearer caller-token",
    }
    to_bags = forwarded_headers(sent, "bags/run1", service_token="service", caller_segments=("lab",))
    assert to_bags == {"Accept": "application/json", "authorization": "Bearer service"}
