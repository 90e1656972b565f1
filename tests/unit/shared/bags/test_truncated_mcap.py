"""Generated MCAP files cut short: the error says which record is cut and where the file ends;
recovery keeps exactly the messages that are complete before the cut, in every chunk compression."""

from __future__ import annotations

import re
from collections.abc import Callable
from pathlib import Path

import pytest
from mcap.records import ChunkIndex

from bagmcp_shared.bags import open_bag
from bagmcp_shared.errors import DamagedBagError
from bagmcp_shared.timebase import iso_from_ns
from tests.fixtures.mcap_cuts import COMPRESSIONS, Written, chunk_indexes, complete_before, cut_copy, write_mcap

Intact = tuple[Path, list[Written]]
Place = Callable[[int, list[ChunkIndex]], int]
PLACES: dict[str, Place] = {
    "early in the second chunk": lambda _, c: c[1].chunk_start_offset + c[1].chunk_length // 4,
    "late in the second chunk": lambda _, c: c[1].chunk_start_offset + c[1].chunk_length * 3 // 4,
    "in the message index after the first chunk": lambda _, c: c[0].chunk_start_offset + c[0].chunk_length + 20,
    "at 30% of the file": lambda size, _: size * 3 // 10,
    "at 80% of the file": lambda size, _: size * 8 // 10,
}
CHUNK_NAMES = {"none": "uncompressed", "lz4": "lz4", "zstd": "zstd"}


@pytest.fixture(scope="module", params=sorted(COMPRESSIONS))
def intact(request: pytest.FixtureRequest, tmp_path_factory: pytest.TempPathFactory) -> Intact:
    compression: str = request.param
    path = tmp_path_factory.mktemp("mcap") / f"{compression}.mcap"
    return path, write_mcap(path, compression)


def _recovered(path: Path) -> tuple[list[tuple[str, int, str]], tuple[str, ...]]:
    with open_bag(path, recover_truncated=True) as bag:
        read = [(raw.connection.topic, raw.log_time_ns, bag.decode(raw).data) for raw in bag.messages()]  # type: ignore[attr-defined]
        return read, bag.summary().notes


def _values(messages: list[Written]) -> list[tuple[str, int, str]]:
    return [(m.topic, m.log_time_ns, m.text) for m in messages]


@pytest.mark.parametrize("place", sorted(PLACES))
def test_recovery_reads_exactly_the_messages_complete_before_the_cut(
    intact: Intact, place: str, tmp_path: Path
) -> None:
    path, written = intact
    cut = PLACES[place](path.stat().st_size, chunk_indexes(path))
    expected = complete_before(path, cut, written)
    read, _ = _recovered(cut_copy(path, cut, tmp_path / "cut.mcap"))
    assert read == _values(expected)
    assert 0 < len(expected) < len(written)


def test_a_cut_compressed_chunk_gives_up_the_complete_messages_at_its_start(intact: Intact, tmp_path: Path) -> None:
    path, written = intact
    second = chunk_indexes(path)[1]
    cut = second.chunk_start_offset + second.chunk_length * 3 // 4
    before = len(complete_before(path, second.chunk_start_offset, written))
    inside = len(complete_before(path, cut, written)) - before
    read, notes = _recovered(cut_copy(path, cut, tmp_path / "cut.mcap"))
    assert inside > 0
    assert len(read) == before + inside
    assert notes == (
        f"the MCAP file is cut short: the {CHUNK_NAMES[second.compression or 'none']} chunk that starts at byte "
        f"{second.chunk_start_offset:,} claims to be {second.chunk_length:,} bytes long (to byte "
        f"{second.chunk_start_offset + second.chunk_length:,}) and runs past the end of the {cut:,}-byte file; "
        f"recovered {before:,} messages before it and {inside:,} complete messages from inside it "
        "(on /left, /right); the rest of it, and anything after it, is lost",
    )


def test_the_error_names_the_cut_chunk_its_claimed_length_the_file_size_and_what_is_recoverable(
    intact: Intact, tmp_path: Path
) -> None:
    path, written = intact
    second = chunk_indexes(path)[1]
    start, length = second.chunk_start_offset, second.chunk_length
    cut = start + length * 3 // 4
    before = len(complete_before(path, start, written))
    inside = len(complete_before(path, cut, written)) - before
    cut_path = cut_copy(path, cut, tmp_path / "cut.mcap")
    with pytest.raises(DamagedBagError) as caught:
        open_bag(cut_path)
    assert str(caught.value) == (
        f"{cut_path}: the MCAP file is cut short: the {CHUNK_NAMES[second.compression or 'none']} chunk that starts "
        f"at byte {start:,} claims to be {length:,} bytes long (to byte {start + length:,}) and runs past the end "
        f"of the {cut:,}-byte file; it holds the messages logged from {iso_from_ns(second.message_start_time)} to "
        f"{iso_from_ns(second.message_end_time)}; the {before:,} messages before it and the first {inside:,} "
        "inside it (on /left, /right) are complete and can be recovered on request (bagmcp info --recover)"
    )


def test_a_file_cut_inside_the_first_chunk_head_has_nothing_to_recover(intact: Intact, tmp_path: Path) -> None:
    path, _ = intact
    first = chunk_indexes(path)[0].chunk_start_offset
    cut_path = cut_copy(path, first + 5, tmp_path / "cut.mcap")
    for recover in (False, True):
        with pytest.raises(DamagedBagError) as caught:
            open_bag(cut_path, recover_truncated=recover)
        assert str(caught.value) == (
            f"{cut_path}: the MCAP file is cut short: the chunk that starts at byte {first:,} is cut inside its "
            f"9-byte head (opcode and length) by the end of the {first + 5:,}-byte file; what it holds is unknown; "
            "no message before it is complete, so nothing can be recovered"
        )


def test_a_file_cut_in_its_summary_opens_with_every_message_and_a_note(intact: Intact, tmp_path: Path) -> None:
    path, written = intact
    cut_path = cut_copy(path, path.stat().st_size - 40, tmp_path / "cut.mcap")
    with open_bag(cut_path) as bag:
        read = [(raw.connection.topic, raw.log_time_ns, bag.decode(raw).data) for raw in bag.messages()]  # type: ignore[attr-defined]
        (note,) = bag.summary().notes
    assert read == _values(written)
    assert note.startswith("the MCAP file's summary section is cut short (the ")
    assert note.endswith(f"-byte file); all {len(written):,} messages are complete and were read from start to end")


def test_an_unchunked_file_cut_inside_a_message_names_its_topic_and_keeps_the_ones_before(tmp_path: Path) -> None:
    path = tmp_path / "flat.mcap"
    written = write_mcap(path, "none", count=300, chunked=False)
    data = path.read_bytes()
    victim = written[200]
    payload_at = data.find(victim.payload)
    cut_path = cut_copy(path, payload_at + 10, tmp_path / "cut.mcap")
    with pytest.raises(DamagedBagError) as caught:
        open_bag(cut_path)
    start = payload_at - 9 - 22
    assert str(caught.value) == (
        f"{cut_path}: the MCAP file is cut short: the message on {victim.topic} that starts at byte {start:,} claims "
        f"to be {9 + 22 + len(victim.payload):,} bytes long (to byte {payload_at + len(victim.payload):,}) and runs "
        f"past the end of the {payload_at + 10:,}-byte file; it holds one message, logged at "
        f"{iso_from_ns(victim.log_time_ns)}; the 200 messages before it are complete and can be recovered on request "
        "(bagmcp info --recover)"
    )
    read, notes = _recovered(cut_path)
    assert read == _values(written[:200])
    assert re.search(r"recovered 200 messages before it; the rest of it, and anything after it, is lost$", notes[0])
