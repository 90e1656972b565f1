"""ROS 1 bags read through a seekable stream by their index at the end, for reads by byte range.

rosbags' reader opens a path and, at open, reads the message index records that follow every chunk
(touching the whole file). This source reads only the bag header, then the index section at its end
(connection records and chunk infos: per chunk its position, time span and message count per
connection), and later only the chunks whose span overlaps a question's window and that hold its
connections (plain, bz2 or lz4, decompressed within the memory budget as ``open_bag``'s chunks are).
Messages come out in log time order, ties in file order, as rosbags gives them. The index's record headers
are parsed with rosbags' own ``Header``; a chunk's records by ``ros1_chunks.message_records``.
"""

from __future__ import annotations

import heapq
import struct
from collections.abc import Callable, Collection, Iterator
from dataclasses import dataclass, replace
from itertools import pairwise
from pathlib import Path
from typing import BinaryIO, TypeVar

from rosbags.rosbag1 import ReaderError
from rosbags.rosbag1.reader import Header, RecordType, normalize, read_bytes, read_uint32
from rosbags.typesys.msg import normalize_msgtype

from bagmcp_shared.bags.models import Compression, Connection, Encoding, RawMessage
from bagmcp_shared.bags.ros1_chunks import COMPRESSED, chunk_decompressor, message_records
from bagmcp_shared.bags.source import ListedSource
from bagmcp_shared.errors import DamagedBagError

MAGIC = b"#ROSBAG V2.0\n"
SAMPLED_CHUNKS = 3  # chunk headers that decide a stored object's compression (see Ros1RangeSource.compression)
_T = TypeVar("_T")
_ERRORS = (ReaderError, KeyError, ValueError, EOFError, AssertionError, struct.error)


@dataclass(frozen=True)
class ChunkSpan:
    """One chunk as the index describes it: where it starts, its log-time span [start, end] and the
    message count of each connection in it."""

    pos: int
    start_ns: int
    end_ns: int
    counts: dict[int, int]


def _connection(stream: BinaryIO) -> Connection:
    header = Header.read(stream, RecordType.CONNECTION)
    conn_id, topic = header.get_uint32("conn"), normalize(header.get_string("topic"))
    data = Header.read(stream)
    definition = data.get_string("message_definition")
    metadata = [("callerid", data.get_string("callerid") if "callerid" in data else "")]
    latching = data.get_string("latching") if "latching" in data else ""
    metadata.append(("latching", str(int(latching) if latching else 0)))
    return Connection(
        id=conn_id,
        topic=topic,
        msgtype=normalize_msgtype(data.get_string("type")),
        encoding=Encoding.ROS1,
        definition=definition,
        definition_format="msg" if definition.strip() else "",
        count=0,
        digest=data.get_string("md5sum"),
        metadata=tuple(metadata),
    )


def _chunk_span(stream: BinaryIO) -> ChunkSpan:
    header = Header.read(stream, RecordType.CHUNK_INFO)
    if header.get_uint32("ver") != 1:
        raise ReaderError("CHUNK_INFO version is not 1")
    count = header.get_uint32("count")
    read_uint32(stream)  # the data length: count pairs of uint32
    counts = {read_uint32(stream): read_uint32(stream) for _ in range(count)}
    return ChunkSpan(header.get_uint64("chunk_pos"), header.get_time("start_time"), header.get_time("end_time"), counts)


class Ros1RangeSource(ListedSource):
    """A ROS 1 bag (format 2.0) read by its end index; ``name`` stands for it in messages."""

    def __init__(self, name: Path, stream: BinaryIO) -> None:
        self._name = name
        self._stream = stream
        try:
            self._connections, self._chunks = self._read_index()
        except _ERRORS as err:
            raise DamagedBagError(
                f"{name}: the ROS 1 bag's index is damaged ({err}); `rosbag reindex` may repair it"
            ) from err
        self._by_id = {c.id: c for c in self._connections}
        if (hint := getattr(stream, "hint_records", None)) is not None:  # a chunk ends where the next starts
            starts = sorted(span.pos for span in self._chunks)
            hint(list(pairwise([*starts, self._index_pos])))  # no chunk: an empty list
        self._bounds: dict[int, tuple[int, int] | None] | None = None
        self._compression: Compression | None = None

    def _read_index(self) -> tuple[list[Connection], list[ChunkSpan]]:
        if self._stream.read(len(MAGIC)) != MAGIC:
            raise ReaderError("not a ROS 1 bag of format 2.0")
        header = Header.read(self._stream, RecordType.BAGHEADER)
        index_pos, chunk_count = header.get_uint64("index_pos"), header.get_uint32("chunk_count")
        self._index_pos = index_pos
        if index_pos == 0:
            raise ReaderError("the bag is not indexed")
        if chunk_count == 0:
            return [], []
        self._stream.seek(index_pos)
        found = [_connection(self._stream) for _ in range(header.get_uint32("conn_count"))]
        chunks = [_chunk_span(self._stream) for _ in range(chunk_count)]
        totals = {c.id: sum(span.counts.get(c.id, 0) for span in chunks) for c in found}
        connections = [replace(c, count=totals[c.id]) for c in found]
        return connections, chunks

    @property
    def compression(self) -> Compression:
        """What most chunks use, from their headers, read on first use (only filter_bag asks, to write its copy
        alike). A local file's every chunk header is read (small reads). A stored object's are not: its file
        fetches a chunk whole when any of it is read, so reading every header fetched the whole bag (1,552 MB
        in 537 requests, 12.7 s, for a 5 s cut of a 2 GB bag); there the first, middle and last chunks decide
        (three chunks, a few MB; a recorder writes one compression throughout)."""
        if self._compression is None:
            chunks = self._chunks
            if getattr(self._stream, "hint_records", None) is not None and len(chunks) > SAMPLED_CHUNKS:
                chunks = [chunks[0], chunks[len(chunks) // 2], chunks[-1]]
            self._compression = Compression.of_chunks(self._chunk_compression(span) for span in chunks)
        return self._compression

    def _chunk_compression(self, span: ChunkSpan) -> str:
        self._stream.seek(span.pos)
        return self._guarded(lambda: Header.read(self._stream, RecordType.CHUNK).get_string("compression"))

    def bounds(self, connection_id: int) -> tuple[int, int] | None:
        """First and last log time of a connection: from the first and last chunk that hold it. Every
        connection's are found on the first call (a reader's summary asks for all of them), each chunk parsed
        once for all the connections it starts or ends, not once per connection: the corpus's example-bz2.bag
        (8,647 messages) decompressed its bz2 chunks again for each connection, 596 ms to open and read it whole
        against 63 ms now (in process, as in ``ros1_chunks.message_records``)."""
        if self._bounds is None:
            self._bounds = self._all_bounds()
        return self._bounds.get(connection_id)

    def _all_bounds(self) -> dict[int, tuple[int, int] | None]:
        """Each connection's bounds from the chunks that start or end it, each chunk parsed once. Nothing is kept
        when a chunk cannot be read: the cause may be the object store's, gone by the next call."""
        ends: dict[int, tuple[ChunkSpan, ChunkSpan]] = {}
        for conn in self._connections:
            holding = [span for span in self._chunks if span.counts.get(conn.id)]
            if holding:
                ends[conn.id] = (min(holding, key=lambda s: s.start_ns), max(holding, key=lambda s: s.end_ns))
        wanted: dict[int, tuple[ChunkSpan, set[int]]] = {}
        for conn_id, pair in ends.items():
            for span in pair:
                wanted.setdefault(span.pos, (span, set()))[1].add(conn_id)
        times: dict[tuple[int, int], list[int]] = {}
        for pos, (span, conn_ids) in sorted(wanted.items()):
            for t, _, cid, _ in self._chunk_messages(span, conn_ids):
                times.setdefault((pos, cid), []).append(t)
        found: dict[int, tuple[int, int] | None] = {c.id: None for c in self._connections}
        for conn_id, (first, last) in ends.items():
            found[conn_id] = (min(self._held(times, first, conn_id)), max(self._held(times, last, conn_id)))
        return found

    def _held(self, times: dict[tuple[int, int], list[int]], span: ChunkSpan, conn_id: int) -> list[int]:
        """The log times of ``conn_id`` in ``span``, which the index says holds some."""
        if not (held := times.get((span.pos, conn_id))):
            topic = self._by_id[conn_id].topic
            raise DamagedBagError(
                f"{self._name}: the index says the chunk at byte {span.pos:,} holds messages of {topic}, but it "
                "holds none; `rosbag reindex` may repair it"
            )
        return held

    def messages(
        self, connection_ids: Collection[int], *, start_ns: int | None, stop_ns: int | None
    ) -> Iterator[RawMessage]:
        """Messages in time order, ties in the order the connections are asked for, then in file order
        (as rosbags merges its per-connection indexes); a chunk is read once no earlier message is left."""
        rank = {cid: n for n, cid in enumerate(dict.fromkeys(connection_ids)) if cid in self._by_id}
        queue: list[tuple[int, int, int, int, int, bytes, ChunkSpan | None]] = []
        for chunk in self._chunks:
            overlaps = (start_ns is None or chunk.end_ns >= start_ns) and (stop_ns is None or chunk.start_ns < stop_ns)
            if overlaps and any(chunk.counts.get(cid) for cid in rank):
                queue.append((chunk.start_ns, -1, chunk.pos, 0, 0, b"", chunk))
        heapq.heapify(queue)
        while queue:
            stamp, _, _, _, conn_id, data, span = heapq.heappop(queue)
            if span is None:
                yield RawMessage(self._by_id[conn_id], stamp, data)
                continue
            for t, offset, cid, payload in self._chunk_messages(span, set(rank)):
                if (start_ns is None or t >= start_ns) and (stop_ns is None or t < stop_ns):
                    heapq.heappush(queue, (t, rank[cid], span.pos, offset, cid, payload, None))

    def _chunk_messages(self, span: ChunkSpan, wanted: Collection[int]) -> list[tuple[int, int, int, bytes]]:
        """(log time, offset, connection, bytes) of the messages of ``wanted`` in one chunk."""
        return self._guarded(lambda: message_records(self._chunk_bytes(span), wanted))

    def _chunk_bytes(self, span: ChunkSpan) -> bytes:
        """A chunk's records decompressed, within the memory budget as every reader's chunks are (see
        ``ros1_chunks``): its declared size is checked first, and a size that lies stops at the limit."""
        self._stream.seek(span.pos)
        header = Header.read(self._stream, RecordType.CHUNK)
        compression = header.get_string("compression")
        data = read_bytes(self._stream, read_uint32(self._stream))
        if compression == "none":
            return data
        if compression not in COMPRESSED:
            raise ReaderError(f"the chunk at byte {span.pos:,} has unknown compression {compression!r}")
        declared = header.get_uint32("size")
        return chunk_decompressor(self._name, span.pos, compression, declared=declared, compressed=len(data))(data)

    def _guarded(self, read: Callable[[], _T]) -> _T:
        try:
            return read()
        except _ERRORS as err:
            raise DamagedBagError(f"{self._name}: a chunk could not be read ({err})") from err

    def close(self) -> None:
        self._stream.close()
