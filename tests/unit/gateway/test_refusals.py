"""A refused call says why: the scope a tool needs when that is all the token lacks (filter_bag needs upload),
else that its profile or allow/deny lists leave the tool out."""

from __future__ import annotations

import mcp.types as types
from mcp.server.auth.provider import AccessToken

from bagmcp_gateway.access.policy import ToolPolicy

FILTER = types.Tool(
    name="filter_bag",
    input_schema={"type": "object"},
    annotations=types.ToolAnnotations(read_only_hint=False, destructive_hint=False),
)


def _token(*scopes: str, **claims: object) -> AccessToken:
    return AccessToken(token="t", client_id="token:t", scopes=list(scopes), claims=claims)


def test_a_read_token_is_told_filter_bag_needs_the_upload_scope() -> None:
    policy = ToolPolicy()
    assert not policy.allows(FILTER, _token("read"))
    assert policy.refusal(FILTER, _token("read")) == (
        "filter_bag needs the upload scope, which this token lacks; an admin can make a token that has it: "
        "bagmcp token create NAME --scopes read,upload"
    )
    assert policy.allows(FILTER, _token("read", "upload"))


def test_a_tool_the_token_s_lists_leave_out_is_not_enabled_whatever_its_scopes() -> None:
    refused = ToolPolicy().refusal(FILTER, _token("read", deny=["filter_*"]))
    assert refused == "filter_bag is not enabled for this token (its profile or allow/deny lists)"
