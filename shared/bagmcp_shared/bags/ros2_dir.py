"""ROS 2 bag directories (and bare storage files): metadata.yaml, split files, compression."""

from __future__ import annotations

import re
from collections.abc import Callable, Collection, Iterator, Mapping, Sequence
from contextlib import ExitStack
from pathlib import Path
from typing import BinaryIO, cast

import yaml
import zstandard

from bagmcp_shared.bags.detect import sniff_file
from bagmcp_shared.bags.mcap_source import McapSource
from bagmcp_shared.bags.models import BagFormat, Compression, Connection, RawMessage
from bagmcp_shared.bags.source import MergedSource, MessageSource, TopicTotals
from bagmcp_shared.bags.sqlite3_source import Sqlite3Source
from bagmcp_shared.bags.user_yaml import UserYamlError, load_user_yaml, read_user_yaml
from bagmcp_shared.budget import check_record, input_budget
from bagmcp_shared.errors import DamagedBagError, UnsupportedFormatError

_STORAGE_SUFFIXES = {".db3": BagFormat.ROS2_SQLITE3, ".mcap": BagFormat.ROS2_MCAP}


def _natural_key(path: Path) -> tuple[str, int]:
    match = re.search(r"(\d+)$", path.name.split(".")[0])
    return (path.name[: match.start()] if match else path.name, int(match.group(1)) if match else -1)


def _one_line(err: Exception) -> str:
    """A parser's error in one line (YAML errors quote the offending text over several)."""
    if isinstance(err, yaml.MarkedYAMLError) and err.problem_mark is not None:
        return f"{err.problem} at line {err.problem_mark.line + 1}, column {err.problem_mark.column + 1}"
    return " ".join(str(err).split())


def _read_metadata(directory: Path) -> dict[str, object] | None:
    path = directory / "metadata.yaml"
    if not path.exists():
        return None
    return _metadata_info(path, lambda: read_user_yaml(path))


def _metadata_info(path: Path, load: Callable[[], object]) -> dict[str, object]:
    """The ``rosbag2_bagfile_information`` of the metadata.yaml at ``path``, as ``load`` parses it."""
    try:
        data = load()
        info = data["rosbag2_bagfile_information"]  # type: ignore[index]
    except UserYamlError as err:
        raise UnsupportedFormatError(
            f"{path}: metadata.yaml {err}; it is refused to bound memory (rosbag2 writes no aliases and far "
            "smaller files): write the values out"
        ) from err
    except (yaml.YAMLError, KeyError, TypeError, UnicodeDecodeError) as err:
        raise DamagedBagError(f"{path}: metadata.yaml is not valid rosbag2 metadata ({_one_line(err)})") from err
    if not isinstance(info, dict):
        raise DamagedBagError(f"{path}: metadata.yaml is not valid rosbag2 metadata")
    return cast(dict[str, object], info)


def _listed_names(directory: Path, info: dict[str, object]) -> list[str]:
    names = info.get("relative_file_paths") or []
    if not isinstance(names, list):
        raise DamagedBagError(f"{directory}/metadata.yaml: relative_file_paths is not a list")
    return [Path(str(n)).name for n in names]


def _listed_files(directory: Path, info: dict[str, object]) -> list[Path]:
    files = [directory / name for name in _listed_names(directory, info)]
    if missing := [f.name for f in files if not f.exists()]:
        raise DamagedBagError(f"{directory}: storage files listed in metadata.yaml are missing: {missing}")
    return files


def _found_files(directory: Path) -> list[Path]:
    files = [p for p in directory.iterdir() if p.suffix in _STORAGE_SUFFIXES and p.is_file()]
    if not files:
        raise UnsupportedFormatError(f"{directory}: no .db3 or .mcap storage files in this directory")
    return sorted(files, key=_natural_key)


def _declared_topics(info: dict[str, object]) -> dict[str, tuple[str, int]]:
    """Topic name -> (serialization format, message count) as metadata.yaml declares them."""
    declared: dict[str, tuple[str, int]] = {}
    entries = info.get("topics_with_message_count")
    for entry in entries if isinstance(entries, list) else []:
        try:
            meta = entry["topic_metadata"]
            declared[str(meta["name"])] = (str(meta["serialization_format"]), int(entry["message_count"]))
        except (KeyError, TypeError, ValueError):
            continue
    return declared


def _counts(connections: Sequence[Connection]) -> dict[str, int]:
    """Each topic's message count over the storage files."""
    actual: dict[str, int] = {}
    for conn in connections:
        actual[conn.topic] = actual.get(conn.topic, 0) + conn.count
    return actual


def _disagreements(info: dict[str, object] | None, actual: Mapping[str, int]) -> list[str]:
    """Notes where metadata.yaml contradicts the storage files (which are what is read; ``actual`` is each
    topic's count in them)."""
    if info is None:
        return []
    notes = []
    for topic, (fmt, count) in sorted(_declared_topics(info).items()):
        if fmt != "cdr":
            notes.append(f"metadata.yaml declares serialization {fmt!r} for {topic}; the storage says cdr")
        if topic in actual and actual[topic] != count:
            notes.append(f"metadata.yaml declares {count} messages on {topic}; the storage holds {actual[topic]}")
    return notes


def _compression_mode(directory: Path, info: dict[str, object] | None) -> str:
    """ "" (none), "file" or "message": how metadata.yaml says the storage is zstd-compressed."""
    if info is None:
        return ""
    mode = str(info.get("compression_mode") or "").lower()
    fmt = str(info.get("compression_format") or "")
    if mode in ("", "none"):
        return ""
    if fmt != "zstd":
        raise UnsupportedFormatError(f"{directory}: compression format {fmt!r} is not supported (zstd is)")
    return mode


def storage_files(directory: Path) -> tuple[list[Path], str, dict[str, object] | None]:
    """The storage files of a bag directory in recording order, compression mode, metadata."""
    info = _read_metadata(directory)
    if info is None:
        return _found_files(directory), "", None
    return _listed_files(directory, info), _compression_mode(directory, info), info


class _DecompressedMessages:
    """Wraps a source whose payloads are zstd-compressed one by one (compression_mode: message)."""

    def __init__(self, inner: MessageSource) -> None:
        self._inner = inner
        self._zstd = zstandard.ZstdDecompressor()

    @property
    def connections(self) -> Sequence[Connection]:
        return self._inner.connections

    @property
    def notes(self) -> Sequence[str]:
        return self._inner.notes

    @property
    def compression(self) -> Compression:
        return Compression.ZSTD_MESSAGE

    def bounds(self, connection_id: int) -> tuple[int, int] | None:
        return self._inner.bounds(connection_id)

    def messages(
        self, connection_ids: Collection[int], *, start_ns: int | None, stop_ns: int | None
    ) -> Iterator[RawMessage]:
        for msg in self._inner.messages(connection_ids, start_ns=start_ns, stop_ns=stop_ns):
            yield msg._replace(data=self._decompressed(msg))

    def _decompressed(self, msg: RawMessage) -> bytes:
        """One message's zstd frame, refused when the size it declares is past the budget; zstd allocates
        that size before it decompresses (and stops at the limit when the frame declares none)."""
        where = f"a zstd-compressed message on {msg.connection.topic} at {msg.log_time_ns} ns"
        declared = zstandard.frame_content_size(msg.data)
        limit = check_record(where, declared_bytes=max(declared, 0), compressed_bytes=len(msg.data))
        return self._zstd.decompress(msg.data, max_output_size=limit)

    def close(self) -> None:
        self._inner.close()


def open_storage_file(path: Path, *, recover_truncated: bool) -> tuple[MessageSource, BagFormat]:
    """One .db3 or .mcap storage file."""
    kind = sniff_file(path)
    if kind is BagFormat.ROS2_SQLITE3:
        return Sqlite3Source(path), kind
    if kind is BagFormat.MCAP:
        return McapSource(path, recover_truncated=recover_truncated), kind
    raise UnsupportedFormatError(f"{path}: a ROS 1 bag cannot be part of a ROS 2 bag directory")


def _decompress_file(path: Path, into: Path) -> Path:
    """A zstd-compressed storage file decompressed into ``into`` as a stream (so to disk, not memory); one
    that expands more than the budget's ``max_expansion`` times (past its floor) is refused while it is
    written, as a decompression bomb."""
    target = into / path.name.removesuffix(".zstd")
    budget = input_budget()
    limit = max(budget.expansion_floor_bytes, int(budget.max_expansion * path.stat().st_size))
    written = 0
    with path.open("rb") as src, target.open("wb") as dst, zstandard.ZstdDecompressor().stream_reader(src) as raw:
        while chunk := raw.read(1 << 20):
            written += len(chunk)
            if written > limit:
                raise UnsupportedFormatError(
                    f"{path}: expands more than {budget.max_expansion:.0f} times when decompressed; refusing it "
                    "as a decompression bomb (BAGMCP_MAX_EXPANSION)"
                )
            dst.write(chunk)
    return target


def open_directory(
    directory: Path, stack: ExitStack, *, recover_truncated: bool, decompress_into: Path
) -> tuple[MessageSource, BagFormat, list[Path]]:
    """All storage files of a ROS 2 bag directory as one source (zstd-compressed files are decompressed into
    ``decompress_into`` first)."""
    files, mode, info = storage_files(directory)
    paths = files
    if mode == "file":
        paths = [_decompress_file(f, decompress_into) for f in files]
    sources: list[MessageSource] = []
    kinds: set[BagFormat] = set()
    for path in paths:
        source, kind = open_storage_file(path, recover_truncated=recover_truncated)
        stack.callback(source.close)
        sources.append(_DecompressedMessages(source) if mode == "message" else source)
        kinds.add(kind)
    fmt = BagFormat.ROS2_SQLITE3 if kinds == {BagFormat.ROS2_SQLITE3} else BagFormat.ROS2_MCAP
    conns = [c for s in sources for c in s.connections]
    compression = {"file": Compression.ZSTD_FILE, "message": Compression.ZSTD_MESSAGE}.get(mode)
    notes = _disagreements(info, _counts(conns))
    return MergedSource(sources, notes=notes, compression=compression), fmt, files


def open_directory_streams(
    directory: Path,
    metadata: bytes | None,
    storage: Mapping[str, tuple[BinaryIO, int]],
    stack: ExitStack,
    *,
    totals: TopicTotals | None = None,
) -> tuple[MessageSource, BagFormat, list[Path]]:
    """A ROS 2 bag directory whose storage files (MCAP or sqlite3) are read through seekable streams (team
    mode reads them where they are stored, by byte ranges): ``metadata`` is metadata.yaml's bytes (None when
    the directory has none), ``storage`` maps each storage file's name to (stream, size). ``totals`` are the
    catalog's count and first/last time of each topic: given, sqlite3 files are not counted (a scan of every
    row), unless the totals cannot stand for them (a topic of two types, or one they lack). The streams are
    closed with ``stack``. zstd-compressed storage files (compression_mode: file) are not read this way:
    they are decompressed whole first, by ``open_directory``."""
    for stream, _ in storage.values():
        stack.callback(stream.close)
    path = directory / "metadata.yaml"
    info = None if metadata is None else _metadata_info(path, lambda: load_user_yaml(metadata.decode("utf-8")))
    mode = _compression_mode(directory, info)
    if mode == "file":
        raise UnsupportedFormatError(f"{directory}: zstd-compressed storage files are not read from a stream")
    names = _listed_names(directory, info) if info is not None else sorted(storage, key=lambda n: _natural_key(Path(n)))
    if missing := [name for name in names if name not in storage]:
        raise DamagedBagError(f"{directory}: storage files listed in metadata.yaml are missing: {missing}")
    sources: list[MessageSource] = []
    uncounted: list[Sqlite3Source] = []
    for name in names:
        source = _stream_source(directory / name, storage[name], counted=totals is None)
        stack.callback(source.close)
        sources.append(_DecompressedMessages(source) if mode == "message" else source)
        if isinstance(source, Sqlite3Source) and totals is not None:
            uncounted.append(source)
    conns = [c for s in sources for c in s.connections]
    if uncounted and not _totals_fit(conns, totals):
        for source in uncounted:
            source.count_rows()
        conns = [c for s in sources for c in s.connections]
        uncounted = []
    totals = totals if uncounted else None  # nothing left uncounted: the files' own counts
    actual = {topic: count for topic, (count, _, _) in totals.items()} if totals is not None else _counts(conns)
    compression = Compression.ZSTD_MESSAGE if mode == "message" else None
    merged = MergedSource(sources, notes=_disagreements(info, actual), compression=compression, totals=totals)
    sqlite3 = bool(names) and all(name.endswith(".db3") for name in names)
    return merged, BagFormat.ROS2_SQLITE3 if sqlite3 else BagFormat.ROS2_MCAP, [directory / name for name in names]


def _totals_fit(connections: Sequence[Connection], totals: TopicTotals | None) -> bool:
    """Whether the bag's per-topic ``totals`` can stand for what ``connections`` would count: every topic
    in them, each of one type."""
    if totals is None:
        return False
    types: dict[str, set[str]] = {}
    for conn in connections:
        types.setdefault(conn.topic, set()).add(conn.msgtype)
    return all(topic in totals and len(kinds) == 1 for topic, kinds in types.items())


def _stream_source(path: Path, stream: tuple[BinaryIO, int], *, counted: bool) -> MessageSource:
    """A storage file read through ``stream``: sqlite3 by its name (``.db3``), else MCAP."""
    if path.suffix == ".db3":
        return Sqlite3Source(path, stream=stream, counted=counted)
    return McapSource(path, stream=stream[0], size=stream[1])
