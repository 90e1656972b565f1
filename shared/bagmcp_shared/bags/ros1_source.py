"""ROS 1 bags (format 2.0, plain/bz2/lz4 chunks) through rosbags' rosbag1 reader and its index, chunks
decompressed within the memory budget (ros1_chunks)."""

from __future__ import annotations

import struct
from collections.abc import Collection, Iterator
from pathlib import Path

from rosbags.interfaces import Connection as RbConnection
from rosbags.interfaces import ConnectionExtRosbag1
from rosbags.rosbag1 import Reader, ReaderError

from bagmcp_shared.bags.models import Compression, Connection, Encoding, RawMessage
from bagmcp_shared.bags.ros1_chunks import bound_chunks
from bagmcp_shared.bags.source import ListedSource
from bagmcp_shared.errors import BagError, DamagedBagError


def _metadata(conn: RbConnection) -> tuple[tuple[str, str], ...]:
    ext = conn.ext
    if not isinstance(ext, ConnectionExtRosbag1):
        return ()
    pairs = [("callerid", ext.callerid or ""), ("latching", str(ext.latching or 0))]
    return tuple(pairs)


def _convert(conn: RbConnection) -> Connection:
    return Connection(
        id=conn.id,
        topic=conn.topic,
        msgtype=conn.msgtype,
        encoding=Encoding.ROS1,
        definition=conn.msgdef.data,
        definition_format="msg" if conn.msgdef.data.strip() else "",
        count=conn.msgcount,
        digest=conn.digest,
        metadata=_metadata(conn),
    )


class Ros1Source(ListedSource):
    """A ROS 1 bag; the bag's index (read at open) gives counts and first/last times."""

    def __init__(self, path: Path) -> None:
        self._reader = Reader(path)
        try:
            self._reader.open()
        except (ReaderError, AssertionError, KeyError, ValueError, IndexError, EOFError) as err:
            detail = str(err).strip() or "its index records are inconsistent"
            raise DamagedBagError(
                f"{path}: the ROS 1 bag's index is damaged ({detail}); `rosbag reindex` may repair it"
            ) from err
        self._path = path
        try:
            chunk_names = bound_chunks(path, self._reader.chunks)
        except (OSError, struct.error, ValueError) as err:
            self._reader.close()
            raise DamagedBagError(f"{path}: a chunk header could not be read ({err})") from err
        except BagError:
            self._reader.close()
            raise
        self._by_id = {c.id: c for c in self._reader.connections}
        self._connections = [_convert(c) for c in self._reader.connections]
        self._compression = Compression.of_chunks(chunk_names)

    @property
    def compression(self) -> Compression:
        """What most chunks use (bz2, lz4 or none), from the chunk headers read at open."""
        return self._compression

    def bounds(self, connection_id: int) -> tuple[int, int] | None:
        index = self._reader.indexes.get(connection_id)
        if not index:
            return None
        return index[0].time, index[-1].time

    def messages(
        self, connection_ids: Collection[int], *, start_ns: int | None, stop_ns: int | None
    ) -> Iterator[RawMessage]:
        wanted = [self._by_id[cid] for cid in connection_ids if cid in self._by_id]
        if not wanted:
            return
        ours = {c.id: c for c in self._connections}
        try:
            for conn, timestamp, data in self._reader.messages(wanted, start_ns, stop_ns):
                yield RawMessage(ours[conn.id], timestamp, data)
        except (ReaderError, AssertionError, EOFError) as err:
            raise DamagedBagError(f"{self._reader.path}: a chunk could not be read ({err})") from err

    def close(self) -> None:
        self._reader.close()
