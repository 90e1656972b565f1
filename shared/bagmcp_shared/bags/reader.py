"""``open_bag``: one interface over every supported input."""

from __future__ import annotations

import logging
import os
import tempfile
from collections.abc import Iterable, Iterator, Mapping, Sequence
from contextlib import ExitStack, contextmanager
from pathlib import Path
from types import TracebackType
from typing import BinaryIO, Self

from bagmcp_shared.bags.decoding import Decoder
from bagmcp_shared.bags.detect import sniff_file
from bagmcp_shared.bags.mcap_source import McapSource
from bagmcp_shared.bags.models import BagFormat, BagSummary, Compression, Connection, RawMessage, TopicSummary
from bagmcp_shared.bags.ros1_ranges import Ros1RangeSource
from bagmcp_shared.bags.ros1_source import Ros1Source
from bagmcp_shared.bags.ros2_dir import open_directory, open_directory_streams, open_storage_file
from bagmcp_shared.bags.source import MessageSource, TopicTotals
from bagmcp_shared.errors import BagError, BagmcpError, DamagedBagError, TopicNotFoundError, UnsupportedFormatError

log = logging.getLogger(__name__)
MESSAGE_CHARS = 600


@contextmanager
def damage_named(path: Path, *, workspace: Path | None = None) -> Iterator[None]:
    """Any failure of a storage library while reading ``path`` (a zstd, lz4 or bz2 stream that does not
    decompress, a record that does not parse, an index that points nowhere) becomes a DamagedBagError
    naming the file; the bag layer's own errors pass through, with files decompressed into ``workspace``
    named as the bag's own."""
    try:
        yield
    except BagError as err:
        shown = _one_line(str(err).replace(str(workspace), str(path)) if workspace is not None else str(err))
        if shown == str(err):
            raise
        raise type(err)(shown) from err
    except BagmcpError:
        raise
    except Exception as err:
        if isinstance(err, OSError) and err.errno is not None:  # the file system, not the data
            raise BagError(f"{path}: cannot be read ({err.strerror})") from err
        log.debug("reading %s failed", path, exc_info=True)
        detail = _one_line(f"{type(err).__name__}: {err}" if str(err) else type(err).__name__)
        raise DamagedBagError(
            f"{path}: the recording is damaged and cannot be read ({detail}); use an intact copy"
        ) from err


def _one_line(message: str, *, limit: int = MESSAGE_CHARS) -> str:
    """An error message in one line of at most ``limit`` characters (libraries quote whole records)."""
    flat = " ".join(message.split())
    return flat if len(flat) <= limit else f"{flat[: limit - 1]}…"


def _guarded(path: Path, workspace: Path | None, messages: Iterator[RawMessage]) -> Iterator[RawMessage]:
    with damage_named(path, workspace=workspace):
        yield from messages


def _size(path: Path, files: Sequence[Path]) -> int:
    return sum(f.stat().st_size for f in files) if path.is_dir() else path.stat().st_size


class BagReader:
    """An open bag: summary, raw messages by topic and time window, decoding."""

    def __init__(
        self,
        path: Path,
        source: MessageSource,
        fmt: BagFormat,
        files: Sequence[Path],
        stack: ExitStack,
        *,
        workspace: Path | None = None,
        size_bytes: int | None = None,
    ) -> None:
        self.path = path
        self._size_bytes = size_bytes
        self._workspace = workspace
        self.format = fmt
        self.files = tuple(files)
        self._source = source
        self._stack = stack
        self._decoder: Decoder | None = None
        self._summary: BagSummary | None = None

    @property
    def connections(self) -> Sequence[Connection]:
        return self._source.connections

    @property
    def compression(self) -> Compression:
        """How the bag's messages are compressed on disk (ROS 1/MCAP chunks, ROS 2 compression_mode)."""
        return self._source.compression

    @property
    def decoder(self) -> Decoder:
        if self._decoder is None:
            self._decoder = Decoder(self._source.connections)
        return self._decoder

    def summary(self) -> BagSummary:
        """Topics with types, counts and first/last log times; computed once."""
        if self._summary is None:
            with damage_named(self.path, workspace=self._workspace):
                self._summary = self._summarize()
        return self._summary

    def _summarize(self) -> BagSummary:
        topics: dict[str, TopicSummary] = {}
        for conn in self._source.connections:
            bounds = self._source.bounds(conn.id) if conn.count else None
            known = topics.get(conn.topic)
            first, last = bounds if bounds else (None, None)
            if known is not None:
                first = min((t for t in (known.first_ns, first) if t is not None), default=None)
                last = max((t for t in (known.last_ns, last) if t is not None), default=None)
            count = conn.count + (known.count if known else 0)
            topics[conn.topic] = TopicSummary(conn.topic, conn.msgtype, count, first, last)
        notes = list(self._source.notes)
        notes += [f"{typ} cannot be decoded: {why}" for typ, why in sorted(self.decoder.problems.items())]
        profile = getattr(self._source, "profile", "")
        return BagSummary(
            path=str(self.path),
            format=self.format,
            size_bytes=self._size_bytes if self._size_bytes is not None else _size(self.path, self.files),
            files=tuple(f.name for f in self.files),
            topics=tuple(sorted(topics.values(), key=lambda t: t.name)),
            profile=profile if isinstance(profile, str) else "",
            notes=tuple(notes),
        )

    def topic_connections(self, topic: str) -> list[Connection]:
        """Connections of ``topic`` (leading slash optional); unknown topics list valid ones."""
        wanted = topic.lstrip("/")
        found = [c for c in self._source.connections if c.topic.lstrip("/") == wanted]
        if not found:
            names = sorted({c.topic for c in self._source.connections})
            raise TopicNotFoundError(
                f"topic {topic!r} is not in {self.path.name}; topics: {', '.join(names) or '(none)'}"
            )
        return found

    def messages(
        self,
        topics: Iterable[str] | None = None,
        *,
        start_ns: int | None = None,
        stop_ns: int | None = None,
    ) -> Iterator[RawMessage]:
        """Raw messages of ``topics`` (all when None) with ``start_ns <= t < stop_ns``, time-ordered."""
        if topics is None:
            ids = [c.id for c in self._source.connections]
        else:
            ids = [c.id for t in topics for c in self.topic_connections(t)]
        return _guarded(self.path, self._workspace, self._source.messages(ids, start_ns=start_ns, stop_ns=stop_ns))

    def decode(self, raw: RawMessage) -> object:
        return self.decoder.decode(raw)

    def close(self) -> None:
        self._stack.close()

    def __enter__(self) -> Self:
        return self

    def __exit__(
        self, exc_type: type[BaseException] | None, exc: BaseException | None, tb: TracebackType | None
    ) -> None:
        self.close()


def _open_flight_log(path: Path, kind: BagFormat) -> MessageSource:
    """pyulog and pymavlink are imported here, when a flight log is opened (about 0.3 s; see foreign.py)."""
    if kind is BagFormat.ULOG:
        from bagmcp_shared.bags.ulog_source import open_ulog

        return open_ulog(path)
    from bagmcp_shared.bags.dataflash_source import open_dataflash

    return open_dataflash(path)


def _open_source(
    path: Path, stack: ExitStack, *, recover_truncated: bool, workspace: Path | None
) -> tuple[MessageSource, BagFormat, list[Path]]:
    if workspace is not None:  # a directory
        return open_directory(path, stack, recover_truncated=recover_truncated, decompress_into=workspace)
    kind = sniff_file(path)
    source: MessageSource
    if kind is BagFormat.ROS1:
        source = Ros1Source(path)
    elif kind is BagFormat.MCAP:
        source = McapSource(path, recover_truncated=recover_truncated)
    elif kind.is_flight_log:
        source = _open_flight_log(path, kind)
    else:
        source, kind = open_storage_file(path, recover_truncated=recover_truncated)
    stack.callback(source.close)
    return source, kind, [path]


def open_bag(path: str | os.PathLike[str], *, recover_truncated: bool = False) -> BagReader:
    """Open any supported bag: a ROS 1 .bag, a ROS 2 directory, a bare .db3 or .mcap file, a PX4 ULog
    or an ArduPilot DataFlash log.

    Raises a :class:`BagError` subclass with a readable message for anything unreadable.
    ``recover_truncated`` accepts an MCAP cut in the middle of a record and keeps what precedes it.
    """
    bag_path = Path(path)
    if not bag_path.exists():
        raise BagError(f"{bag_path}: no such file or directory")
    stack = ExitStack()
    workspace = (
        Path(stack.enter_context(tempfile.TemporaryDirectory(prefix="bagmcp-bag-"))) if bag_path.is_dir() else None
    )
    try:
        with damage_named(bag_path, workspace=workspace):
            source, fmt, files = _open_source(bag_path, stack, recover_truncated=recover_truncated, workspace=workspace)
    except BagError:
        stack.close()
        raise
    return BagReader(bag_path, source, fmt, files, stack, workspace=workspace)


def open_stream(name: Path, stream: BinaryIO, *, size: int, fmt: BagFormat) -> BagReader:
    """Open a bare MCAP file or a ROS 1 bag read through a seekable ``stream`` of ``size`` bytes (team
    mode reads bags where they are stored, by byte ranges); ``name`` stands for the file in messages.
    Closing the reader closes the stream."""
    stack = ExitStack()
    stack.callback(stream.close)
    try:
        with damage_named(name):
            source: MessageSource
            if fmt is BagFormat.ROS1:
                source = Ros1RangeSource(name, stream)
            elif fmt is BagFormat.MCAP:
                source = McapSource(name, stream=stream, size=size)
            else:
                raise UnsupportedFormatError(f"{name}: {fmt} bags are not read from a stream")
    except BaseException:
        stack.close()
        raise
    return BagReader(name, source, fmt, [name], stack, size_bytes=size)


def open_directory_stream(
    name: Path,
    metadata: bytes | None,
    storage: Mapping[str, tuple[BinaryIO, int]],
    *,
    totals: TopicTotals | None = None,
) -> BagReader:
    """Open a ROS 2 bag directory of MCAP or sqlite3 storage files, each read through a seekable stream
    (see ``open_directory_streams``, and ``totals`` there); ``name`` stands for the directory in messages.
    Closing the reader closes the streams."""
    stack = ExitStack()
    try:
        with damage_named(name):
            source, fmt, files = open_directory_streams(name, metadata, storage, stack, totals=totals)
    except BaseException:
        stack.close()
        raise
    size = sum(size for _, size in storage.values())  # as a local directory counts it: its storage files
    return BagReader(name, source, fmt, files, stack, size_bytes=size)
