"""The cut recordings in ../shared/data/bags: the truncated one's error and what recovery reads from
its only (zstd) chunk; the one without summary still reads whole. Compared with the intact original."""

from __future__ import annotations

import json
from collections import Counter
from pathlib import Path

import pytest
from mcap.records import Channel, Message
from mcap.stream_reader import StreamReader

from bagmcp_cli.main import main
from bagmcp_shared.bags import open_bag
from bagmcp_shared.errors import DamagedBagError

pytestmark = pytest.mark.corpus

INTACT = "ros2_mcap/evo_nav2_turtlebot/nav2_turtlebot.mcap"
TRUNCATED = "edge_cases/derived/nav2_turtlebot_truncated_60pct.mcap"
NO_SUMMARY = "edge_cases/derived/nav2_turtlebot_no_summary_no_footer.mcap"
RECOVERED = {"/amcl_pose": 102, "/odom": 2104, "/tf": 4333, "/tf_static": 1}  # 6,540 of the chunk's 8,197
CUT_CHUNK = (
    "the zstd chunk that starts at byte 58 claims to be 362,459 bytes long (to byte 362,517) and runs past the end "
    "of the 303,237-byte file"
)
Stored = tuple[str, int, bytes]


def _intact_in_file_order(corpus: Path) -> list[Stored]:
    """Every message of the original recording in the order its chunk stores them (read by the mcap library)."""
    topics: dict[int, str] = {}
    found: list[Stored] = []
    with (corpus / INTACT).open("rb") as file:
        for record in StreamReader(file).records:
            if isinstance(record, Channel):
                topics[record.id] = record.topic
            elif isinstance(record, Message):
                found.append((topics[record.channel_id], record.log_time, record.data))
    return found


def _read(path: Path, *, recover: bool = False) -> tuple[list[Stored], tuple[str, ...]]:
    with open_bag(path, recover_truncated=recover) as bag:
        read = [(raw.connection.topic, raw.log_time_ns, raw.data) for raw in bag.messages()]
        return read, bag.summary().notes


def _truncated_error(corpus: Path) -> str:
    return (
        f"{corpus / TRUNCATED}: the MCAP file is cut short: {CUT_CHUNK}; it holds all the messages, logged from "
        "2026-05-08T09:59:13.382747Z to 2026-05-08T10:00:50.738043Z; its first 6,540 messages (on /amcl_pose, "
        "/odom, /tf, /tf_static) are complete and can be recovered on request (bagmcp info --recover)"
    )


def test_the_truncated_recording_error_says_which_chunk_is_cut_and_what_can_be_recovered(corpus: Path) -> None:
    with pytest.raises(DamagedBagError) as caught:
        open_bag(corpus / TRUNCATED)
    assert str(caught.value) == _truncated_error(corpus)


def test_recovery_streams_6540_complete_messages_out_of_the_cut_zstd_chunk(corpus: Path) -> None:
    read, notes = _read(corpus / TRUNCATED, recover=True)
    assert Counter(topic for topic, _, _ in read) == RECOVERED
    assert read == _intact_in_file_order(corpus)[:6540]
    assert notes == (
        f"the MCAP file is cut short: {CUT_CHUNK}; recovered 6,540 complete messages from inside it (on "
        "/amcl_pose, /odom, /tf, /tf_static); the rest of it, and anything after it, is lost",
    )


def test_the_recording_without_summary_still_reads_all_8197_messages(corpus: Path) -> None:
    read, notes = _read(corpus / NO_SUMMARY)
    assert read == _intact_in_file_order(corpus)
    assert len(read) == 8197
    assert notes == (
        "the MCAP file has no summary or index (recording cut off?); all 8197 messages were recovered by reading "
        "it from start to end",
    )


def test_bagmcp_info_recover_reports_the_recovered_counts_and_the_note(
    corpus: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["info", "--json", str(corpus / TRUNCATED)]) == 1
    refused = capsys.readouterr()
    assert (refused.out, refused.err) == ("", f"bagmcp: error: {_truncated_error(corpus)}\n")
    assert main(["info", "--json", "--recover", str(corpus / TRUNCATED)]) == 0
    info = json.loads(capsys.readouterr().out)
    assert {t["name"]: t["count"] for t in info["topics"]} == RECOVERED
    assert info["message_count"] == 6540
    assert info["notes"][0].startswith(f"the MCAP file is cut short: {CUT_CHUNK}; recovered 6,540")
