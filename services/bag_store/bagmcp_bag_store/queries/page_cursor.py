"""get_messages_in_range's page cursors, tamper-evident: each carries an HMAC over its numbers and what it was
given for (bag, topic, window, ``every``), so a forged total ("5 of -1 messages") or a cursor of another
topic is refused with a sentence instead of being believed.

The key is derived from the service credential in team mode (every bag-store of a team accepts the others'
cursors and a restart keeps them valid); an embedded server draws a random one at start, so its cursors last
as long as the process. Signing and checking cost one SHA-256 HMAC (a few microseconds) per page."""

from __future__ import annotations

import hashlib
import hmac
import re
import secrets
from dataclasses import dataclass

from bagmcp_shared.errors import ArgumentError

_TAG_HEX = 32  # 128 bits of the HMAC: forging one is out of reach
_TEXT = re.compile(rf"^(\d{{1,20}}):(\d{{1,12}}):(\d{{1,12}}):(\d{{1,12}}):([0-9a-f]{{{_TAG_HEX}}})$")


def cursor_key(service_token: str | None) -> bytes:
    """The signing key: from the service credential when there is one (shared by a team), else random."""
    if service_token:
        return hashlib.sha256(b"bagmcp page cursor\0" + service_token.encode()).digest()
    return secrets.token_bytes(32)


@dataclass(frozen=True)
class PageScope:
    """What a cursor is valid for: the bag (its id), topic, window and thinning of the request that made it."""

    bag_id: str
    topic: str
    lo_ns: int
    hi_ns: int
    every: int

    def text(self) -> str:
        return f"{self.bag_id}\0{self.topic}\0{self.lo_ns}\0{self.hi_ns}\0{self.every}"


@dataclass(frozen=True)
class Cursor:
    """Where the next page starts: its first log time, how many messages at that instant were shown
    already, the window's total, and the position of that message in the window (for ``every``)."""

    stamp_ns: int
    skip: int
    total: int
    position: int = 0

    def numbers(self) -> str:
        return f"{self.stamp_ns}:{self.skip}:{self.total}:{self.position}"


class CursorSigner:
    """Makes cursor texts and reads them back, refusing any it did not make for the same request."""

    def __init__(self, key: bytes) -> None:
        self._key = key

    def _tag(self, cursor: Cursor, scope: PageScope) -> str:
        message = f"{scope.text()}\0{cursor.numbers()}".encode()
        return hmac.new(self._key, message, hashlib.sha256).hexdigest()[:_TAG_HEX]

    def dump(self, cursor: Cursor, scope: PageScope) -> str:
        return f"{cursor.numbers()}:{self._tag(cursor, scope)}"

    def parse(self, text: str | None, scope: PageScope) -> Cursor | None:
        """The cursor ``text`` names; ArgumentError when it was not made here for this bag, topic, window and
        ``every`` (altered, from another request, or from a bag-store run before a restart)."""
        if not text:
            return None
        match = _TEXT.match(text.strip())
        refused = ArgumentError(
            "this cursor is not one get_messages_in_range returned for this bag, topic, start/end and every "
            "(or the service restarted since); call again without cursor to start from the first page"
        )
        if match is None:
            raise refused
        cursor = Cursor(*(int(match.group(i)) for i in range(1, 5)))
        if not hmac.compare_digest(match.group(5), self._tag(cursor, scope)):
            raise refused
        return cursor
