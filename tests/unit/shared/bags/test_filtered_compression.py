"""A filtered copy keeps its source's compression (ROS 1 bz2/lz4 chunks, MCAP zstd/lz4 chunks,
rosbag2 per-file/per-message zstd), so with fewer messages it is smaller than its source; across
formats it gets the output format's usual compression. Files are inspected directly."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import pytest

from bagmcp_shared.bags import Compression, open_bag
from bagmcp_shared.bags.writer import (
    FilterCancelled,
    FilterResult,
    FilterSpec,
    OutputFormat,
    default_output,
    write_filtered,
)
from tests.fixtures import scenario as sc
from tests.fixtures.bagfactory import BagKind
from tests.fixtures.compressed_bags import (
    COMPRESSED_KINDS,
    COMPRESSION_OF,
    CompressedKind,
    size_bytes,
    stored_compression,
)

DROP = FilterSpec(exclude_topics=(sc.SCAN_TOPIC, sc.TF_TOPIC))
KEPT = sorted(set(sc.COUNTS) - {sc.SCAN_TOPIC, sc.TF_TOPIC})


def _filter(
    source: Path, out_dir: Path, spec: FilterSpec = DROP, fmt: OutputFormat | None = None, name: str = "out"
) -> FilterResult:
    with open_bag(source) as bag:
        fmt = fmt or default_output(bag.format, bag.connections)
        return write_filtered(bag, out_dir, name, fmt=fmt, spec=spec)


def _payloads(path: Path, topics: list[str]) -> list[tuple[str, int, bytes]]:
    with open_bag(path) as bag:
        return [(raw.connection.topic, raw.log_time_ns, raw.data) for raw in bag.messages(topics)]


def _files(path: Path) -> dict[str, bytes]:
    if path.is_file():
        return {path.name: path.read_bytes()}
    return {p.name: p.read_bytes() for p in sorted(path.iterdir())}


def _speeds(path: Path) -> list[float]:
    """linear.x of every /cmd_vel message, decoded."""
    with open_bag(path) as bag:
        return [bag.decode(raw).linear.x for raw in bag.messages([sc.CMD_TOPIC])]  # type: ignore[attr-defined]


@dataclass(frozen=True)
class Copies:
    kind: CompressedKind
    source: Path
    first: FilterResult
    second: FilterResult


@pytest.fixture(scope="module", params=COMPRESSED_KINDS)
def copies(
    request: pytest.FixtureRequest,
    compressed_bags: dict[CompressedKind, Path],
    tmp_path_factory: pytest.TempPathFactory,
) -> Copies:
    """Two filtered copies (same request, separate directories) of one compressed source."""
    kind: CompressedKind = request.param
    first = _filter(compressed_bags[kind], tmp_path_factory.mktemp(f"{kind}-a"))
    second = _filter(compressed_bags[kind], tmp_path_factory.mktemp(f"{kind}-b"))
    return Copies(kind, compressed_bags[kind], first, second)


# Within a format -------------------------------------------------------------------------------


def test_the_generated_sources_are_compressed_as_intended(compressed_bags: dict[CompressedKind, Path]) -> None:
    stored = {kind: stored_compression(path) for kind, path in compressed_bags.items()}
    assert stored == {kind: {c.value} for kind, c in COMPRESSION_OF.items()}


def test_a_filtered_copy_is_compressed_like_its_source(copies: Copies) -> None:
    expected = COMPRESSION_OF[copies.kind]
    assert copies.first.compression is expected
    assert copies.first.compression_note == f"{expected.label}, as in the source"
    assert stored_compression(copies.first.path) == {expected.value}
    with open_bag(copies.first.path) as bag:
        assert bag.compression is expected


def test_a_filtered_copy_holds_the_source_messages_of_the_kept_topics(copies: Copies) -> None:
    assert copies.first.counts == {t: sc.COUNTS[t] for t in KEPT}
    assert _payloads(copies.first.path, KEPT) == _payloads(copies.source, KEPT)
    assert _speeds(copies.first.path) == pytest.approx([sc.cmd_speed_at(t) for t in sc.ticks(sc.CMD_HZ)])
    with open_bag(copies.first.path) as bag:
        assert {t.name for t in bag.summary().topics} == set(KEPT)
        assert sum(1 for raw in bag.messages() if bag.decode(raw) is not None) == sum(copies.first.counts.values())
        assert bag.decoder.problems == {}


def test_a_filtered_copy_is_smaller_than_its_source(copies: Copies) -> None:
    assert size_bytes(copies.first.path) < size_bytes(copies.source)


def test_a_compressed_copy_is_byte_identical_when_made_twice(copies: Copies) -> None:
    assert copies.first.counts == copies.second.counts
    assert _files(copies.first.path) == _files(copies.second.path)


REAL_COMPRESSED = [
    ("ros1/turtlesim_rosbagjs/example-bz2.bag", Compression.BZ2, ("/tf", "/turtle1/color_sensor")),
    ("ros1/turtlesim_rosbagjs/example-lz4.bag", Compression.LZ4, ("/tf", "/turtle1/color_sensor")),
    ("ros1/husky_gps_imu_odom/test1.bag", Compression.BZ2, ("/imu/data",)),
    ("ros2_mcap/evo_nav2_turtlebot", Compression.ZSTD, ("/tf",)),
    ("ros2_mcap/rosbag2_wbag_split", Compression.ZSTD, ("AAA", "BBB")),
]


@pytest.mark.corpus
@pytest.mark.parametrize(("relative", "expected", "dropped"), REAL_COMPRESSED)
def test_real_compressed_recordings_filter_to_smaller_copies_with_the_same_compression(
    corpus: Path, tmp_path: Path, relative: str, expected: Compression, dropped: tuple[str, ...]
) -> None:
    source = corpus / relative
    with open_bag(source) as bag:
        kept = sorted({c.topic for c in bag.connections} - set(dropped))
        assert bag.compression is expected
    spec = FilterSpec(exclude_topics=dropped)
    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    first = _filter(source, tmp_path / "a", spec)
    second = _filter(source, tmp_path / "b", spec)
    assert first.compression is expected
    assert stored_compression(first.path) == {expected.value}
    assert _payloads(first.path, kept) == _payloads(source, kept)
    assert size_bytes(first.path) < size_bytes(source)
    assert _files(first.path) == _files(second.path)


# Across formats --------------------------------------------------------------------------------

ACROSS = [
    ("ros1-bz2", OutputFormat.ROS2_MCAP, Compression.ZSTD),
    ("ros1-lz4", OutputFormat.ROS2_MCAP, Compression.ZSTD),
    ("ros1-lz4", OutputFormat.ROS2_SQLITE3, Compression.ZSTD_FILE),
    ("mcap-zstd", OutputFormat.ROS1, Compression.BZ2),
    ("mcap-lz4", OutputFormat.ROS2_SQLITE3, Compression.ZSTD_FILE),
    ("sqlite3-zstd-message", OutputFormat.ROS2_MCAP, Compression.ZSTD),
    ("sqlite3-zstd-file", OutputFormat.ROS1, Compression.BZ2),
]


@pytest.mark.parametrize(("kind", "fmt", "expected"), ACROSS)
def test_a_compressed_source_converted_to_another_format_gets_that_formats_usual_compression(
    compressed_bags: dict[CompressedKind, Path],
    tmp_path: Path,
    kind: CompressedKind,
    fmt: OutputFormat,
    expected: Compression,
) -> None:
    result = _filter(compressed_bags[kind], tmp_path, fmt=fmt)
    source = COMPRESSION_OF[kind]
    assert result.compression is expected
    assert result.compression_note == f"{expected.label}, the {fmt.value} counterpart of the source's {source.label}"
    assert stored_compression(result.path) == {expected.value}
    assert _speeds(result.path) == _speeds(compressed_bags[kind])


@pytest.mark.parametrize("fmt", tuple(f for f in OutputFormat if f is not OutputFormat.MCAP_JSON))
def test_an_uncompressed_source_stays_uncompressed_in_every_format(
    scenario_bags: dict[BagKind, Path], tmp_path: Path, fmt: OutputFormat
) -> None:
    result = _filter(scenario_bags["ros1"], tmp_path, fmt=fmt)
    assert (result.compression, result.compression_note) == (Compression.NONE, "no compression, as in the source")
    assert stored_compression(result.path) == {"none"}


# Progress and cancellation ---------------------------------------------------------------------


def test_the_last_progress_report_says_which_compression_was_used(
    compressed_bags: dict[CompressedKind, Path], tmp_path: Path
) -> None:
    reports: list[str] = []
    with open_bag(compressed_bags["ros1-lz4"]) as bag:
        write_filtered(
            bag, tmp_path, "p", fmt=OutputFormat.ROS2_MCAP, spec=DROP, progress=lambda _f, m: reports.append(m)
        )
    written = sum(sc.COUNTS[t] for t in KEPT)
    note = "zstd chunks, the ros2-mcap counterpart of the source's lz4 chunks"
    assert reports[-1] == f"wrote {written} messages to p ({note})"


@pytest.mark.parametrize("kind", COMPRESSED_KINDS)
def test_cancelling_a_compressed_copy_leaves_nothing_behind(
    compressed_bags: dict[CompressedKind, Path], tmp_path: Path, kind: CompressedKind
) -> None:
    polls: list[int] = []

    def cancelled() -> bool:
        polls.append(1)
        return len(polls) >= 4

    with open_bag(compressed_bags[kind]) as bag:
        fmt = default_output(bag.format, bag.connections)
        with pytest.raises(FilterCancelled):
            write_filtered(bag, tmp_path, "partial", fmt=fmt, spec=FilterSpec(), cancelled=cancelled)
    assert list(tmp_path.iterdir()) == []
