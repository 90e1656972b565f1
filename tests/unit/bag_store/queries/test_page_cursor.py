"""Page cursors signed with a key from the service credential hold across a team's bag-stores and restarts;
an embedded server's random key makes its cursors its own."""

from __future__ import annotations

import pytest

from bagmcp_bag_store.queries.page_cursor import Cursor, CursorSigner, PageScope, cursor_key
from bagmcp_shared.errors import ArgumentError

SCOPE = PageScope("bag-1", "/odom", 0, 10_000, 1)


def test_bag_stores_sharing_a_service_credential_read_each_other_s_cursors() -> None:
    made = CursorSigner(cursor_key("team-credential")).dump(Cursor(500, 1, 42, 7), SCOPE)
    assert CursorSigner(cursor_key("team-credential")).parse(made, SCOPE) == Cursor(500, 1, 42, 7)
    for other in (cursor_key("another-team"), cursor_key(None)):
        with pytest.raises(ArgumentError, match="call again without cursor"):
            CursorSigner(other).parse(made, SCOPE)
    assert cursor_key(None) != cursor_key(None)
