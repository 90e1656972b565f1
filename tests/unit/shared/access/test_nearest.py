"""``OpenBag.nearest`` reads a window around the time asked for, widening it only when it holds no message. The
window is half an average period either side: on a regular topic it holds one message, the nearest. With two
periods either side it held three or four, and a cold image read from the object store fetched every chunk
holding them: 16 MB of 1 MB images where one chunk of 2 MB holds the answer."""

from __future__ import annotations

from collections.abc import Iterator

import pytest

from bagmcp_shared.bags import RawMessage
from bagmcp_shared.errors import DamagedBagError
from tests.fixtures.inprocess import InProcess


def _nearest_of(times: list[int], stamp: int) -> int:
    return min(times, key=lambda t: abs(t - stamp))


@pytest.mark.parametrize("topic", ["/scan", "/odom", "/imu"])
def test_a_regular_topic_reads_one_message_the_nearest(
    served_drive: InProcess, monkeypatch: pytest.MonkeyPatch, topic: str
) -> None:
    access = served_drive.composition.embedded.resources.access
    with access.open("drive_mcap") as bag:
        times = [m.log_time_ns for m in bag.reader.messages([topic])]
        assert len(times) > 10
        read: list[RawMessage] = []
        every = bag.reader.messages

        def counted(*args: object, **kwargs: object) -> Iterator[RawMessage]:
            for message in every(*args, **kwargs):  # type: ignore[arg-type]
                read.append(message)
                yield message

        monkeypatch.setattr(bag.reader, "messages", counted)
        for i in (0, len(times) // 3, len(times) - 2):
            for fraction in (0.3, 0.7):  # nearer the one message, then the next
                stamp = times[i] + int(fraction * (times[i + 1] - times[i]))
                read.clear()
                assert bag.nearest(topic, stamp).log_time_ns == _nearest_of(times, stamp)
                assert len(read) == 1, f"{len(read)} messages read around {stamp}"


def test_every_topic_gives_its_nearest_message_at_the_bags_start_middle_and_end(served_drive: InProcess) -> None:
    """Topics that start late or end early need the window widened at the bag's ends."""
    access = served_drive.composition.embedded.resources.access
    with access.open("drive") as bag:
        for topic in (t.name for t in bag.summary.topics if t.count):
            times = [m.log_time_ns for m in bag.reader.messages([topic])]
            for stamp in (bag.start_ns, (bag.start_ns + bag.end_ns) // 2 + 1, bag.end_ns):
                assert bag.nearest(topic, stamp).log_time_ns == _nearest_of(times, stamp), topic


def test_a_topic_the_bag_no_longer_gives_is_a_damaged_bag_not_a_search_without_end(
    served_drive: InProcess, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The catalog counts /odom's messages; a reader that finds none (a file damaged since ingest) widened the
    window for ever before."""
    access = served_drive.composition.embedded.resources.access
    with access.open("drive_db3") as bag:
        monkeypatch.setattr(bag.reader, "messages", lambda *args, **kwargs: iter(()))
        with pytest.raises(DamagedBagError, match=r"bag drive_db3: the catalog counts [\d,]+ messages of /odom, but"):
            bag.nearest("/odom", (bag.start_ns + bag.end_ns) // 2)
