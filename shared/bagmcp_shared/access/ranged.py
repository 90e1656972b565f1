"""A read-only, seekable file over one stored object, read by byte ranges through the block cache.

A bag library that seeks and reads (the ``mcap`` reader: footer, summary, then only the chunks a
question needs) fetches just those blocks from the object store. Reads that continue where the last
one ended also fetch ``read_ahead_bytes`` more in the same request, so a streaming reader makes few,
large requests. Wrong data is impossible: every range response carries the object's ETag and size
(``Content-Range``), which must be the ones the file was opened with, and must hold every byte asked
for; anything else is an error naming the bag.

Opening costs no request when the catalog records the file's ETag and size (a single-file bag): the
first range read checks them. Each request is a round trip in sequence with the reader's next one (20 ms
on a network object store), so a HEAD before it would add a round trip to every cold read. The catalog
records the size of each file, a ROS 2 directory's too; for a directory stored before it did, the first read
of each file's block 0 (which its readers read first anyway) brings it. Only a bag stored before ETags were
recorded is opened with a HEAD.
"""

from __future__ import annotations

import bisect
import io
import time
from dataclasses import dataclass
from functools import partial
from typing import TYPE_CHECKING, Protocol

from bagmcp_shared.access.blocks import BlockCache, object_id
from bagmcp_shared.access.files import at_once
from bagmcp_shared.errors import DamagedBagError, ObjectNotFoundError, StorageError
from bagmcp_shared.storage import ObjectInfo
from bagmcp_shared.storage.base import UNKNOWN_TOTAL, RangeAnswer

if TYPE_CHECKING:
    from _typeshed import WriteableBuffer

STREAMING = 2  # reads in a row that continue the last one before read-ahead starts (one chunk: one)
RETRY_PAUSES_S = (0.2, 1.0)  # a failed request is tried again after these pauses, then the read fails
MEMORY_BLOCKS = 2  # blocks a file keeps in memory (see RangedFile)


class RangeStore(Protocol):
    """What ranged reads need of an object store (S3Store has it)."""

    @property
    def bucket(self) -> str: ...

    def stat(self, key: str) -> ObjectInfo: ...

    def read_range_tagged(self, key: str, *, offset: int, length: int) -> RangeAnswer: ...


UNKNOWN_SIZE = -1


@dataclass(frozen=True)
class StoredFile:
    """One bag file as the catalog knows it: the bag's name (for errors), its key, size (UNKNOWN_SIZE for
    a ROS 2 directory's files: the catalog records their sum) and ETag ("" when the catalog recorded none)."""

    bag: str
    key: str
    size: int
    etag: str = ""


def changed(bag: str, what: str) -> DamagedBagError:
    return DamagedBagError(
        f"bag {bag} changed in the object store after it was catalogued ({what}), so it is not read; "
        "upload the bag again"
    )


def pinned(store: RangeStore, stored: StoredFile) -> StoredFile:
    """``stored`` with the ETag every range read must carry and its size, from a HEAD of the object (checked
    against the catalog's size and ETag where it records them)."""
    try:
        found = store.stat(stored.key)
    except ObjectNotFoundError as err:
        raise StorageError(
            f"bag {stored.bag} is missing from the object store ({stored.key}); delete it and upload it again"
        ) from err
    if stored.size != UNKNOWN_SIZE and found.size != stored.size:
        raise changed(stored.bag, f"{found.size} bytes, the catalog recorded {stored.size}")
    if stored.etag and found.etag and found.etag != stored.etag:
        raise changed(stored.bag, f"ETag {found.etag}, the catalog recorded {stored.etag}")
    return StoredFile(stored.bag, stored.key, found.size, stored.etag or found.etag)


class RangedFile(io.BufferedIOBase):
    """``read``/``seek``/``tell`` over a stored object; keeps the two blocks last read in memory for small
    reads. Two, not one: SQLite reading a time window alternates between a page of the timestamp index
    and a page of rows, which lie in different blocks; with one block kept, each switch read a whole block
    from the disk cache again (reading one topic of a 317.6 MB ``.db3`` from a warm cache took 2.2 s with
    one block kept, 0.9 s with two; the local file 0.4-0.6 s). It costs a block more of memory per open file.

    Buffered, not raw: the ``mcap`` reader wraps raw streams in a ``BufferedReader`` of its own, which
    reads ahead past the record it wants and closes the stream when it is collected."""

    def __init__(self, store: RangeStore, stored: StoredFile, blocks: BlockCache, *, read_ahead_bytes: int) -> None:
        super().__init__()
        self._store = store
        self._tag_recorded = bool(stored.etag)  # the ETag is the catalog's (else a HEAD's)
        self._recorded = stored.size != UNKNOWN_SIZE  # the size is the catalog's (else a HEAD's or block 0's)
        self._stored = stored = stored if stored.etag else pinned(store, stored)
        self._blocks = blocks
        self._etag = stored.etag
        self._obj = object_id(store.bucket, stored.key, self._etag)
        self._block = blocks.block_bytes
        self._ahead = max(read_ahead_bytes // self._block, 0)
        self._pos = 0
        self._next = -2  # the block after the last one read: a read starting there continues
        self._streak = 0  # reads in a row that continued the one before
        self._mem: dict[int, bytes] = {}  # the blocks last read, at most MEMORY_BLOCKS, oldest first
        self._records: list[tuple[int, int]] = []  # (start, stop) of records a reader reads whole

    @property
    def size(self) -> int:
        """The object's size in bytes (read with block 0 when the catalog recorded none)."""
        if self._stored.size == UNKNOWN_SIZE:
            self._learn_size()
        return self._stored.size

    @property
    def size_known(self) -> bool:
        """Whether the size is known without a read (the catalog's, or a HEAD's at opening)."""
        return self._stored.size != UNKNOWN_SIZE

    @property
    def identity(self) -> str:
        """What the stored content is: a hash of its bucket, key and ETag (its blocks' directory name)."""
        return self._obj

    def hint_records(self, spans: list[tuple[int, int]]) -> None:
        """Tell the file the byte spans of records that are read whole (a bag's chunks, from its index):
        a miss inside one then fetches the rest of it in the same request (a chunk's header and body are
        two reads; without the hint they cost two requests)."""
        self._records = sorted(spans)

    def prefetch_ends(self) -> None:
        """Fetch the first block and the last ``block_bytes`` at once: a bag reader reads its header, then its
        index or summary at the end (ROS 1: connections and chunk infos; MCAP: footer and summary), which
        were two round trips one after the other (20 ms each on a network object store)."""
        count = -(-self.size // self._block)
        tail = max((self.size - self._block) // self._block, 0)
        runs = [(0, count - 1)] if tail <= 1 else [(0, 0), (tail, count - 1)]
        at_once([partial(self._fetch_missing, first, last) for first, last in runs])

    def prefetch_head(self) -> None:
        """Fetch the first block (with it the object's size, when the catalog recorded none) and keep it in memory,
        as the reader reads it next."""
        if self._stored.size == UNKNOWN_SIZE:
            self._learn_size()
        elif 0 not in self._mem:
            self._remember(0, self._blocks_of(0, 0, 0)[0])

    def _fetch_missing(self, first: int, last: int) -> None:
        if not self._blocks.path(self._obj, first).exists():
            self._fetch_run(first, last)

    def readable(self) -> bool:
        return True

    def seekable(self) -> bool:
        return True

    def tell(self) -> int:
        return self._pos

    def seek(self, offset: int, whence: int = io.SEEK_SET) -> int:
        base = {io.SEEK_SET: 0, io.SEEK_CUR: self._pos, io.SEEK_END: self.size}[whence]
        if base + offset < 0:
            raise ValueError(f"negative seek position {base + offset}")
        self._pos = base + offset
        return self._pos

    def read1(self, size: int = -1) -> bytes:
        return self.read(size)

    def read(self, size: int | None = -1) -> bytes:
        stop = self.size if size is None or size < 0 else min(self._pos + size, self.size)
        if stop <= self._pos:
            return b""
        start, self._pos = self._pos, stop
        first = start // self._block
        if (held := self._mem.get(first)) is not None and stop <= (first + 1) * self._block:
            return held[start - first * self._block : stop - first * self._block]
        return self._range(start, stop)

    def readinto(self, buffer: WriteableBuffer) -> int:
        view = memoryview(buffer).cast("B")
        data = self.read(len(view))
        view[: len(data)] = data
        return len(data)

    def _range(self, start: int, stop: int) -> bytes:
        first, last = start // self._block, (stop - 1) // self._block
        count = -(-self.size // self._block)
        self._streak = self._streak + 1 if first in (self._next, self._next - 1) else 0
        ahead = min(last + self._ahead, count - 1) if self._streak >= STREAMING else last
        ahead = max(ahead, min(self._record_end(start) // self._block, count - 1))
        self._next = last + 1
        parts = self._blocks_of(first, last, ahead)
        self._remember(last, parts[-1])
        joined = parts[0] if len(parts) == 1 else b"".join(parts)
        return joined[start - first * self._block : stop - first * self._block]

    def _remember(self, index: int, block: bytes) -> None:
        self._mem.pop(index, None)
        self._mem[index] = block
        while len(self._mem) > MEMORY_BLOCKS:
            del self._mem[next(iter(self._mem))]

    def _record_end(self, offset: int) -> int:
        """The last byte of the hinted record holding ``offset`` (``offset`` when none does)."""
        at = bisect.bisect_right(self._records, (offset, 2**63)) - 1
        if at >= 0 and self._records[at][0] <= offset < self._records[at][1]:
            return self._records[at][1] - 1
        return offset

    def _blocks_of(self, first: int, last: int, ahead: int) -> list[bytes]:
        """Blocks ``first`` .. ``last`` from memory, disk or one request per missing run (which also
        fetches missing blocks up to ``ahead``)."""
        parts: list[bytes] = []
        index = first
        while index <= last:
            found = self._mem.get(index)
            if found is None:
                found = self._blocks.cached(self._obj, index)
            if found is None:
                fetched = self._fetch_run(index, max(ahead, last))
                parts += fetched[: last - index + 1]
                index += len(fetched)
            else:
                parts.append(found)
                index += 1
        return parts

    def _fetch_run(self, first: int, last: int) -> list[bytes]:
        with self._blocks.claim(self._obj, first, last) as end:
            found = self._blocks.cached(self._obj, first)  # another process fetched it while we waited
            if found is not None:
                return [found]
            offset = first * self._block
            data = self._get(offset, min((end + 1) * self._block, self.size) - offset)
            parts = [data[at : at + self._block] for at in range(0, len(data), self._block)]
            self._blocks.store(self._obj, first, parts)
            return parts

    def _learn_size(self) -> None:
        """Read block 0 (kept, as any fetched block) and take the object's size from the answer; a HEAD when
        the server sent no size."""
        answer = self._request(0, self._block)
        if answer.total == UNKNOWN_TOTAL:
            self._stored = pinned(self._store, self._stored)
            return
        self._stored = StoredFile(self._stored.bag, self._stored.key, answer.total, self._etag)
        self._checked(answer, 0, min(self._block, answer.total))
        if answer.data:
            self._blocks.store(self._obj, 0, [answer.data])
            self._remember(0, answer.data)

    def _get(self, offset: int, length: int) -> bytes:
        """``length`` bytes at ``offset`` from the object store, checked to be all there."""
        return self._checked(self._request(offset, length), offset, length)

    def _checked(self, answer: RangeAnswer, offset: int, length: int) -> bytes:
        """The answer's bytes, once its object is known to be the one opened and every byte asked came back."""
        stored = self._stored
        if answer.total not in (UNKNOWN_TOTAL, stored.size):
            opened = "the catalog recorded" if self._recorded else "opened as"
            raise changed(stored.bag, f"{answer.total} bytes, {opened} {stored.size}")
        if len(answer.data) != length:
            raise changed(stored.bag, f"{len(answer.data)} of {length} bytes came back at offset {offset}")
        return answer.data

    def _request(self, offset: int, length: int) -> RangeAnswer:
        """A ranged GET with bounded retries of failed requests, its ETag checked against the one opened."""
        stored = self._stored
        for attempt, pause in enumerate((*RETRY_PAUSES_S, None)):
            try:
                answer = self._store.read_range_tagged(stored.key, offset=offset, length=length)
            except ObjectNotFoundError as err:
                raise StorageError(
                    f"bag {stored.bag} is missing from the object store ({stored.key}); delete it and upload it again"
                ) from err
            except StorageError as err:
                if pause is None:
                    raise StorageError(
                        f"bag {stored.bag} could not be read after {attempt + 1} tries: {err} "
                        "Try again once the object store is back."
                    ) from err
                time.sleep(pause)
                continue
            if answer.etag and answer.etag != self._etag:
                opened = "the catalog recorded" if self._tag_recorded else "opened as"
                raise changed(stored.bag, f"ETag {answer.etag}, {opened} {self._etag}")
            return answer
        raise AssertionError("unreachable")  # the last pause is None
