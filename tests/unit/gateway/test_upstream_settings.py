"""The gateway's upstream settings: BAGMCP_UPSTREAMS items and how long an upstream may take to connect and list
its tools (BAGMCP_UPSTREAM_TIMEOUT_S) before it counts as down."""

from __future__ import annotations

from bagmcp_gateway.settings import GatewaySettings
from bagmcp_shared.settings import Env

BASE = {
    "BAGMCP_UPSTREAMS": "bag-store=http://127.0.0.1:8101/mcp,!weather=http://127.0.0.1:9000/mcp@wx#30",
    "BAGMCP_SERVICE_TOKEN": "a-service-token-long-enough-for-the-check-0123456789",
    "BAGMCP_TOKENS": "client-token",
}


def test_every_upstream_waits_ten_seconds_to_list_unless_told_otherwise() -> None:
    default = GatewaySettings.from_env(Env(BASE))
    assert [(u.name, u.timeout_s, u.call_timeout_s, u.prefix) for u in default.upstreams] == [
        ("bag-store", 10.0, 600.0, None),
        ("weather", 10.0, 30.0, "wx"),
    ]
    quick = GatewaySettings.from_env(Env({**BASE, "BAGMCP_UPSTREAM_TIMEOUT_S": "3"}))
    assert [u.timeout_s for u in quick.upstreams] == [3.0, 3.0]
    assert quick.upstreams[1].service_token is None  # a third-party server never gets the service token
