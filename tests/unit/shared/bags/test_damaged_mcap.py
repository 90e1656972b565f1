"""MCAP files without a summary that hold garbage: every failure is one clear DamagedBagError, fast.

The files are the data section of a generated recording (no summary, so they are read from start
to end) with bytes replaced, appended or scrambled.
"""

from __future__ import annotations

import random
import time
from pathlib import Path

import pytest

from bagmcp_shared.bags import open_bag
from bagmcp_shared.errors import DamagedBagError
from tests.fixtures.mcap_cuts import COMPRESSIONS, Written, chunk_indexes, complete_before, data_section, write_mcap

HEADER_END = 41  # magic and header record of the files written here
Recording = tuple[Path, list[Written], bytes]


@pytest.fixture(scope="module")
def recordings(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Recording]:
    """One recording per chunk compression."""
    made: dict[str, Recording] = {}
    for compression in COMPRESSIONS:
        path = tmp_path_factory.mktemp("mcap") / f"{compression}.mcap"
        written = write_mcap(path, compression)
        made[compression] = (path, written, data_section(path))
    return made


@pytest.fixture
def recording(recordings: dict[str, Recording]) -> Recording:
    return recordings["zstd"]


def _write(tmp_path: Path, data: bytes) -> Path:
    path = tmp_path / "damaged.mcap"
    path.write_bytes(data)
    return path


def _error(path: Path, *, recover: bool) -> str:
    with pytest.raises(DamagedBagError) as caught:
        open_bag(path, recover_truncated=recover).close()
    return str(caught.value)


def _data_field_at(index_start: int) -> int:
    """Where a zstd chunk's compressed records begin: head, times, size, CRC, "zstd", records length."""
    return index_start + 9 + 8 + 8 + 8 + 4 + 4 + len("zstd") + 8


def test_a_recording_without_summary_reads_every_message(recording: Recording, tmp_path: Path) -> None:
    _, written, data = recording
    with open_bag(_write(tmp_path, data)) as bag:
        assert sum(1 for _ in bag.messages()) == len(written)


def test_random_bytes_after_the_header_are_named_as_no_mcap_record(recording: Recording, tmp_path: Path) -> None:
    _, _, data = recording
    path = _write(tmp_path, data[:HEADER_END] + b"\xf5" + (2**63).to_bytes(8, "little") + bytes(100))
    for recover in (False, True):
        assert _error(path, recover=recover) == (
            f"{path}: the MCAP file is damaged: the record with opcode 0xf5 that starts at byte 41 claims a length "
            "of 9,223,372,036,854,775,808 bytes, so it is not an MCAP record; it holds no messages; no message "
            "before it is complete, so nothing can be recovered"
        )


def test_zero_bytes_after_the_header_are_not_a_record(recording: Recording, tmp_path: Path) -> None:
    _, _, data = recording
    path = _write(tmp_path, data[:HEADER_END] + bytes(5000))
    assert _error(path, recover=True) == (
        f"{path}: the MCAP file is damaged: the record with opcode 0x00 that starts at byte 41 is not an MCAP "
        "record (no record has opcode 0x00); it holds no messages; no message before it is complete, so nothing "
        "can be recovered"
    )


def test_a_chunk_that_does_not_decompress_stops_the_read_and_recovery_keeps_the_chunks_before(
    recording: Recording, tmp_path: Path
) -> None:
    source, written, data = recording
    second = chunk_indexes(source)[1].chunk_start_offset
    at = _data_field_at(second)
    path = _write(tmp_path, data[:at] + bytes(4) + data[at + 4 :])
    message = _error(path, recover=False)
    assert f"the zstd chunk that starts at byte {second:,} does not decompress (" in message
    assert message.endswith(
        "; none of its messages can be read; the 677 messages before it are complete and can be recovered on "
        "request (bagmcp info --recover)"
    )
    with open_bag(path, recover_truncated=True) as bag:
        times = [raw.log_time_ns for raw in bag.messages()]
    assert times == [m.log_time_ns for m in complete_before(source, second, written)]
    assert len(times) == 677


def test_an_unknown_chunk_compression_is_named(recording: Recording, tmp_path: Path) -> None:
    _, _, data = recording
    compression_at = HEADER_END + 9 + 8 + 8 + 8 + 4 + 4
    path = _write(tmp_path, data[:compression_at] + b"brot" + data[compression_at + 4 :])
    assert "the brot chunk that starts at byte 41 uses compression 'brot', which bagmcp cannot read" in _error(
        path, recover=False
    )


@pytest.mark.parametrize("compression", sorted(COMPRESSIONS))
@pytest.mark.parametrize("seed", range(25))
def test_scrambled_bytes_open_or_fail_with_a_damaged_bag_error_within_a_second(
    recordings: dict[str, Recording], tmp_path: Path, compression: str, seed: int
) -> None:
    _, _, data = recordings[compression]
    rng = random.Random(seed)
    scrambled = bytearray(data[: rng.randrange(HEADER_END, len(data))])
    for _ in range(rng.randrange(1, 6)):
        at = rng.randrange(HEADER_END, len(scrambled)) if len(scrambled) > HEADER_END else HEADER_END
        scrambled[at : at + rng.randrange(1, 64)] = rng.randbytes(rng.randrange(1, 64))
    path = _write(tmp_path, bytes(scrambled))
    began = time.monotonic()
    outcomes = [_outcome(path, recover=recover) for recover in (False, True)]
    assert time.monotonic() - began < 1.0
    for outcome in outcomes:
        assert outcome == "read" or (outcome.startswith(f"{path}: the MCAP file is ") and "\n" not in outcome)


def _outcome(path: Path, *, recover: bool) -> str:
    """ "read" when every message could be read, else the damaged-bag error's message (other errors fail the test)."""
    try:
        with open_bag(path, recover_truncated=recover) as bag:
            sum(1 for _ in bag.messages())
    except DamagedBagError as err:
        return str(err)
    return "read"
