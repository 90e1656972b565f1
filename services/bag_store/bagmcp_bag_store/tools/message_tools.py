"""The declarations of reading messages: get_message_at_time, get_messages_in_range (short tools; their params
models live beside their queries in queries/messages.py)."""

from __future__ import annotations

from bagmcp_bag_store.queries.column_range import messages_as_columns
from bagmcp_bag_store.queries.messages import (
    MessageAtTimeParams,
    MessageRangeParams,
    get_message_at_time,
    get_messages_in_range,
)
from bagmcp_bag_store.reports import MessageAtTime, MessageRange
from bagmcp_bag_store.tools.store import Reading
from bagmcp_kit.declared import Declared
from bagmcp_shared.jobs import Progress


def _in_range(reading: Reading, params: MessageRangeParams, progress: Progress) -> MessageRange:
    if params.in_columns:
        return messages_as_columns(reading.access, params, budget_bytes=reading.budget_bytes)
    return get_messages_in_range(reading.access, params, budget_bytes=reading.budget_bytes, signer=reading.cursors)


def _range_summary(r: MessageRange) -> str:
    if r.columns is not None:
        return f"{r.returned} points of {r.total} messages of {r.topic}" + (
            " (thinned, extremes kept)" if r.downsampled else ""
        )
    return f"{r.returned} of {r.total} messages of {r.topic}" + (
        " (truncated; pass next_cursor for more)" if r.truncated else ""
    )


MESSAGE_AT_TIME = Declared[Reading, MessageAtTimeParams, MessageAtTime](
    "get_message_at_time",
    "The message of a topic nearest a time (log time), and how far it is from that time. "
    'Example: topic="/odom", time=12.5.',
    MessageAtTimeParams,
    MessageAtTime,
    lambda reading, p, _: get_message_at_time(reading.access, p, budget_bytes=reading.budget_bytes),
    lambda r: f"{r.topic} at {r.message.time.offset_s:.3f} s ({r.delta_s:+.3f} s from the requested time)",
    long=False,
)
MESSAGES_IN_RANGE = Declared[Reading, MessageRangeParams, MessageRange](
    "get_messages_in_range",
    "Messages of a topic in a window, oldest first, in pages (next_cursor); layout=columns gives compact arrays "
    'of numeric `fields` (max_points with fields implies it). Example: topic="/odom", layout="columns".',
    MessageRangeParams,
    MessageRange,
    _in_range,
    _range_summary,
    long=False,
)
