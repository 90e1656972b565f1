"""bag_info explains a rate that would mislead instead of printing it bare."""

from __future__ import annotations

from bagmcp_bag_store.queries.catalog_queries import topic_note
from bagmcp_shared.catalog import TopicStats

START = 1_700_000_000_000_000_000


def _topic(count: int, span_ns: int) -> TopicStats:
    rate = (count - 1) * 1e9 / span_ns if span_ns else None
    return TopicStats(
        name="/a", type="std_msgs/msg/String", count=count, first_ns=START, last_ns=START + span_ns, rate_hz=rate
    )


def test_messages_stamped_within_microseconds_get_a_note_saying_the_rate_means_nothing() -> None:
    note = topic_note(_topic(804, 2_000))
    assert note is not None
    assert "804 messages are stamped within 2.0 µs" in note
    assert "401,500,000 Hz" in note


def test_an_ordinary_topic_has_no_note() -> None:
    assert topic_note(_topic(100, 10_000_000_000)) is None
    assert topic_note(_topic(1, 0)) is None
