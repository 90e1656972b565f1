"""Reading many messages while saying how far along it is: the one place decoders report progress."""

from __future__ import annotations

from collections.abc import Callable, Iterable, Iterator

from bagmcp_shared.bags.models import RawMessage

ReportProgress = Callable[[float, str], None]


def counted(
    messages: Iterable[RawMessage], *, expected: int, progress: ReportProgress | None, what: str, every: int = 1000
) -> Iterator[RawMessage]:
    """The messages, reporting the share read so far (below 1) every ``every`` messages."""
    total = max(expected, 1)
    for number, raw in enumerate(messages):
        if progress is not None and number % every == 0:
            progress(min(number / total, 0.99), f"read {number} of {expected} messages of {what}")
        yield raw
