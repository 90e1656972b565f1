"""The MCAP summary read with one read of its section equals the library's record-by-record read on generated
and recorded files, and files without a summary or with a damaged footer give what they gave before (the
library's own read decides those, so McapSource opens them with the same notes or the same error)."""

from __future__ import annotations

import io
from collections.abc import Iterator
from pathlib import Path

import pytest
from mcap.reader import SeekingReader
from mcap.summary import Summary

from bagmcp_shared.bags import mcap_source, mcap_summary
from bagmcp_shared.bags.mcap_records import MAGIC_BYTES
from bagmcp_shared.bags.mcap_source import McapSource
from bagmcp_shared.bags.mcap_summary import SummaryAtOnceReader, summary_at_once
from tests.fixtures.bagfactory import BagKind
from tests.fixtures.mcap_cuts import data_section, write_mcap

LIMIT = 4 << 30  # the library's default record size limit, which McapSource keeps
FOOTER_BYTES = 29  # opcode, length, summary start, summary offset start, CRC
Outcome = tuple[object, ...]


@pytest.fixture(scope="module")
def many_chunks(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """3,000 messages in ~1 KB chunks: about 1,080 chunk indexes, a summary of about 100 KB."""
    path = tmp_path_factory.mktemp("many") / "many.mcap"
    write_mcap(path, "none", count=3000, chunk_bytes=1000)
    return path


def fields(summary: Summary | None) -> Outcome | None:
    if summary is None:
        return None
    parts = (summary.schemas, summary.channels, summary.chunk_indexes)
    return (summary.statistics, *parts, summary.attachment_indexes, summary.metadata_indexes)


def library_summary(data: bytes) -> Outcome:
    """What the library's reader gives for the file ``data``: its summary, or its error."""
    try:
        return ("summary", fields(SeekingReader(io.BytesIO(data)).get_summary()))
    except Exception as err:
        return ("error", type(err), str(err))


def reader_summary(data: bytes) -> Outcome:
    """What SummaryAtOnceReader gives, asked twice (the second answer is the first, kept)."""
    try:
        reader = SummaryAtOnceReader(io.BytesIO(data))
        first = reader.get_summary()
        assert reader.get_summary() is first
        return ("summary", fields(first))
    except Exception as err:
        return ("error", type(err), str(err))


def assert_read_at_once(path: Path) -> None:
    data = path.read_bytes()
    library = SeekingReader(io.BytesIO(data)).get_summary()
    assert library is not None
    assert library.chunk_indexes
    assert library.statistics is not None
    assert fields(summary_at_once(io.BytesIO(data), LIMIT)) == fields(library)  # at once, no fallback
    assert reader_summary(data) == ("summary", fields(library))


def mcap_files(path: Path) -> list[Path]:
    return [path] if path.is_file() else sorted(path.glob("*.mcap"))


def test_generated_files_read_at_once_equal_the_library(
    drive_bags: dict[BagKind, Path], scenario_bags: dict[BagKind, Path], many_chunks: Path
) -> None:
    files = [*mcap_files(drive_bags["ros2-mcap"]), *mcap_files(scenario_bags["ros2-mcap"]), many_chunks]
    assert len(files) == 3
    for path in files:
        assert_read_at_once(path)


def test_every_recorded_mcap_gives_what_the_library_gives(corpus: Path) -> None:
    """Every MCAP of the corpus, the damaged ones too (no footer, cut at 60%: the library's read decides)."""
    files = sorted(corpus.rglob("*.mcap"))
    assert len(files) >= 15
    indexed = 0
    for path in files:
        data = path.read_bytes()
        library = library_summary(data)
        assert reader_summary(data) == library, path
        if library[0] == "summary" and library[1] is not None:
            assert fields(summary_at_once(io.BytesIO(data), LIMIT)) == library[1], path
            indexed += 1
    assert indexed >= 15


def opened(path: Path) -> Outcome:
    """McapSource's connections, notes and compression for ``path``, or its error."""
    try:
        source = McapSource(path)
    except Exception as err:
        return ("error", type(err), str(err))
    with_counts = [(c.topic, c.count) for c in source.connections]
    source.close()
    return ("opened", with_counts, list(source.notes), source.compression)


def assert_as_before(path: Path, monkeypatch: pytest.MonkeyPatch) -> Outcome:
    """McapSource opens ``path`` as it did with the library's reader; the summaries agree too."""
    with monkeypatch.context() as before:
        before.setattr(mcap_source, "SummaryAtOnceReader", SeekingReader)
        expected = opened(path)
    assert opened(path) == expected
    assert reader_summary(path.read_bytes()) == library_summary(path.read_bytes())
    return expected


def footer_at(data: bytes) -> int:
    return len(data) - MAGIC_BYTES - FOOTER_BYTES


def with_summary_start(data: bytes, start: int) -> bytes:
    at = footer_at(data) + 9
    return data[:at] + start.to_bytes(8, "little") + data[at + 8 :]


def damaged(many_chunks: Path) -> Iterator[tuple[str, bytes]]:
    data = many_chunks.read_bytes()
    summary_start = int.from_bytes(data[footer_at(data) + 9 : footer_at(data) + 17], "little")
    at = footer_at(data)
    yield "no footer opcode", data[:at] + b"\x00" + data[at + 1 :]
    yield "a footer length that is not 20", data[: at + 1] + (999).to_bytes(8, "little") + data[at + 9 :]
    yield "summary start past the footer", with_summary_start(data, at + 5)
    yield "summary start inside a record", with_summary_start(data, summary_start + 3)
    yield "summary start at the header", with_summary_start(data, MAGIC_BYTES)
    yield "summary start at the footer", with_summary_start(data, at)
    yield "the summary's last record cut", data[: at - 5] + data[at:]
    yield "only the header", data[:41]
    index = _first_chunk_index(data, summary_start) + 9  # its content: four u64 fields, then the offsets' bytes
    offsets_bytes = int.from_bytes(data[index + 32 : index + 36], "little")
    yield (
        "chunk index offsets not whole",
        data[: index + 32] + (offsets_bytes - 5).to_bytes(4, "little") + data[index + 36 :],
    )
    name_at = index + 36 + offsets_bytes + 8
    yield "chunk index name past it", data[:name_at] + (1 << 20).to_bytes(4, "little") + data[name_at + 4 :]


def _first_chunk_index(data: bytes, at: int) -> int:
    """Where the first chunk index record of the summary starting at ``at`` begins."""
    while data[at] != 0x08:
        at += 9 + int.from_bytes(data[at + 1 : at + 9], "little")
    return at


def test_a_file_without_a_summary_opens_as_before(
    many_chunks: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A footer whose summary start is 0: no summary (read from start to end, with the note saying so)."""
    footer = bytes([0x02]) + (20).to_bytes(8, "little") + bytes(20)
    path = tmp_path / "unindexed.mcap"
    path.write_bytes(data_section(many_chunks) + footer + data_section(many_chunks)[:MAGIC_BYTES])
    assert summary_at_once(io.BytesIO(path.read_bytes()), LIMIT) is None
    outcome = assert_as_before(path, monkeypatch)
    assert outcome[:2] == ("opened", [("/left", 1500), ("/right", 1500)])
    assert "no summary" in str(outcome[2])


def test_files_with_a_damaged_footer_or_summary_give_what_they_gave_before(
    many_chunks: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    outcomes = {}
    for name, data in damaged(many_chunks):
        path = tmp_path / f"{name.replace(' ', '_')}.mcap"
        path.write_bytes(data)
        outcomes[name] = assert_as_before(path, monkeypatch)
    assert outcomes["no footer opcode"][0] == "opened"  # read from start to end, as before
    assert "summary section is damaged" in str(outcomes["no footer opcode"][2])
    assert outcomes["summary start at the header"] == opened(many_chunks)  # everything read, the summary kept
    assert outcomes["a footer length that is not 20"] == opened(many_chunks)  # the library reads past it
    assert "all 0 messages" in str(outcomes["only the header"][2])


class LargestRead(io.BytesIO):
    """A file's bytes in memory that keep the largest read asked of them."""

    largest = 0

    def read(self, size: int | None = -1) -> bytes:
        data = super().read(size)
        self.largest = max(self.largest, len(data))
        return data


def test_a_section_past_the_bound_is_read_record_by_record(many_chunks: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Past SUMMARY_AT_ONCE_MAX_BYTES no read holds the section: the library reads it record by record."""
    data = many_chunks.read_bytes()
    at_once = LargestRead(data)
    expected = fields(SummaryAtOnceReader(at_once).get_summary())
    section = footer_at(data) - int.from_bytes(data[footer_at(data) + 9 : footer_at(data) + 17], "little")
    assert at_once.largest > section
    monkeypatch.setattr(mcap_summary, "SUMMARY_AT_ONCE_MAX_BYTES", section - 1)
    by_records = LargestRead(data)
    assert fields(SummaryAtOnceReader(by_records).get_summary()) == expected
    assert by_records.largest < 4096
