"""A ROS 2 sqlite3 storage file (``.db3``) opened from a seekable stream, not a path.

Python's sqlite3 module opens a database by path only, so team mode used to copy a ``.db3`` whole from
the object store before its first answer. apsw (a maintained SQLite binding) lets Python serve SQLite's
file reads: one process-wide VFS, ``bagmcp-stream``, whose files read pages from the stream they were
opened with (team mode's ``RangedFile``: byte ranges through the host's block cache). SQLite reads a
page at a page-aligned offset (``page_size``, 4 KiB in rosbag2's files); a page in a block that is not
on disk fetches that whole block (``BAGMCP_BLOCK_BYTES``), so a query costs the blocks its b-tree pages fall
in, not the pages: a point read walks the timestamp index and the rows it points to (a few pages each).
Measured on a generated 317.6 MB ``.db3`` (450 000 strings of 600 bytes on one topic, 45 000 on another):
opening it with the catalog's topic stats fetched 2.1 MB and a point read 2.1 MB more with 1 MiB blocks
(4.2 MB, 1.3 % of the file), 0.2 + 0.26 MB with 64 KiB blocks. Without those stats the per-topic count
scans every row, which fetches the whole file (317.6 MB, streamed through the bounded cache, nothing kept
whole): that happens only when the catalog's totals cannot stand for the files' (a topic recorded with two
types), once per file and process. A file without rosbag2's ``timestamp_idx`` makes every time window a
scan too.

The database is opened read-only with ``immutable=1`` and the file says it is immutable
(``SQLITE_IOCAP_IMMUTABLE``): SQLite takes no locks and never looks for a ``-wal`` or ``-journal`` file
(a recording's side files are not part of a stored bag; the object is pinned by its ETag, so it cannot
change underneath). An error the stream raises (the object changed, a short read, the store down) is
raised as it is, naming the bag: apsw hands SQLite an I/O error and re-raises the stream's exception.
"""

from __future__ import annotations

import secrets
import threading
from typing import BinaryIO

import apsw

VFS_NAME = "bagmcp-stream"
IMMUTABLE = 0x2000  # SQLITE_IOCAP_IMMUTABLE: the content never changes while it is open
_SECTOR_BYTES = 4096


class _StreamFile:
    """One open database file: reads go to ``stream``; every write SQLite could try is refused."""

    def __init__(self, stream: BinaryIO, size: int) -> None:
        self._stream = stream
        self._size = size
        self._lock = threading.Lock()  # one connection per file, but SQLite may be entered from any thread

    def xRead(self, amount: int, offset: int) -> bytes:  # noqa: N802 (apsw's method names)
        with self._lock:
            self._stream.seek(offset)
            return self._stream.read(amount)

    def xFileSize(self) -> int:  # noqa: N802
        return self._size

    def xClose(self) -> None:  # noqa: N802
        """The stream belongs to whoever opened the database (the reader closes it)."""

    def xLock(self, level: int) -> None:  # noqa: N802
        """Nothing to lock: the content cannot change."""

    def xUnlock(self, level: int) -> None:  # noqa: N802
        """Nothing was locked."""

    def xCheckReservedLock(self) -> bool:  # noqa: N802
        return False

    def xSectorSize(self) -> int:  # noqa: N802
        return _SECTOR_BYTES

    def xDeviceCharacteristics(self) -> int:  # noqa: N802
        return IMMUTABLE

    def xFileControl(self, op: int, ptr: int) -> bool:  # noqa: N802
        return False  # no file control is understood: SQLite falls back to its defaults

    def xSync(self, flags: int) -> None:  # noqa: N802
        """Nothing is ever written."""

    def xWrite(self, data: bytes, offset: int) -> None:  # noqa: N802
        raise OSError("a stored bag is read-only")

    def xTruncate(self, newsize: int) -> None:  # noqa: N802
        raise OSError("a stored bag is read-only")


class _StreamVfs(apsw.VFS):
    """Opens the files registered in ``pending`` (each once, by the name it was registered under);
    everything else (time, randomness) is the default VFS's."""

    def __init__(self) -> None:
        super().__init__(VFS_NAME, "")  # "": the default VFS for what is not overridden
        self.pending: dict[str, _StreamFile] = {}
        self.guard = threading.Lock()

    def xOpen(  # type: ignore[override]  # noqa: N802
        self, name: str | apsw.URIFilename | None, flags: list[int]
    ) -> _StreamFile | apsw.VFSFile:
        """A registered bag file; or, for a file without a name, SQLite's own scratch file on local disk
        (the default VFS's, deleted when closed): a GROUP BY that sorts more rows than fit in memory spills
        there (the per-topic count spills topic ids and timestamps, never message data)."""
        if name is None:
            return super().xOpen(name, flags)
        filename = name.filename() if isinstance(name, apsw.URIFilename) else name
        with self.guard:
            found = self.pending.pop(filename, None)
        if found is None:  # a journal or WAL: an immutable read-only database never opens one
            raise OSError(f"{filename}: only stored bag files are opened through {VFS_NAME}")
        return found

    def xAccess(self, pathname: str, flags: int) -> bool:  # noqa: N802
        return False  # no side file (-wal, -journal) exists for a stored bag

    def xFullPathname(self, name: str) -> str:  # noqa: N802
        return name

    def xDelete(self, filename: str, syncdir: bool) -> None:  # noqa: N802
        raise OSError("a stored bag is read-only")


_VFS: list[_StreamVfs] = []  # registered once per process, on first use (apsw keeps it while referenced)
_VFS_LOCK = threading.Lock()


def _vfs() -> _StreamVfs:
    with _VFS_LOCK:
        if not _VFS:
            _VFS.append(_StreamVfs())
        return _VFS[0]


def connect_stream(stream: BinaryIO, size: int) -> apsw.Connection:
    """A read-only connection to the SQLite database in ``stream`` (``size`` bytes). SQLite opens the
    main file while it connects, so the registration is used and gone when this returns."""
    vfs = _vfs()
    name = f"/{VFS_NAME}/{secrets.token_hex(8)}.db3"
    with vfs.guard:
        vfs.pending[name] = _StreamFile(stream, size)
    try:
        return apsw.Connection(
            f"file:{name}?immutable=1&mode=ro",
            flags=apsw.SQLITE_OPEN_READONLY | apsw.SQLITE_OPEN_URI,
            vfs=VFS_NAME,
        )
    finally:
        with vfs.guard:
            vfs.pending.pop(name, None)
