"""What the gateway tells services about a restricted token: the names of the tools it may call (None for a
token that may call every tool), from its profile, allow/deny lists and scopes."""

from __future__ import annotations

import mcp.types as types
from mcp.server.auth.provider import AccessToken

from bagmcp_gateway.access.policy import ToolPolicy
from bagmcp_kit.arguments import READ_ONLY

TOOLS = [
    types.Tool(name=n, input_schema={"type": "object"}, annotations=READ_ONLY)
    for n in ("list_bags", "query_bags", "analyze_logs")
]


def _token(**claims: object) -> AccessToken:
    return AccessToken(token="-", client_id="t", scopes=["read"], claims=claims)


def test_a_token_that_may_call_every_tool_is_not_restricted() -> None:
    assert ToolPolicy().callable_names(TOOLS, _token()) is None
    assert ToolPolicy().callable_names(TOOLS, None) is None


def test_allow_and_deny_lists_and_the_global_list_name_what_a_token_may_call() -> None:
    assert ToolPolicy().callable_names(TOOLS, _token(deny=["analyze_*"])) == ["list_bags", "query_bags"]
    assert ToolPolicy().callable_names(TOOLS, _token(allow=["query_bags"])) == ["query_bags"]
    assert ToolPolicy(disabled=("list_bags",)).callable_names(TOOLS, None) == ["query_bags", "analyze_logs"]
