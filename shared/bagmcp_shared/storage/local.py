"""LocalStore: objects as files under one directory (embedded mode, tests)."""

from __future__ import annotations

import os
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from stat import S_ISREG
from typing import BinaryIO

from bagmcp_shared.errors import InvalidKeyError, ObjectNotFoundError, StorageError
from bagmcp_shared.storage.base import (
    ObjectInfo,
    StreamPutters,
    check_range,
    is_valid_key,
    validate_key,
    validate_prefix,
    write_atomically,
)


class LocalStore(StreamPutters):
    """Keys map to files under ``root``; writes are atomic; nothing resolves outside ``root``."""

    def __init__(self, root: Path, *, read_only: bool = False) -> None:
        self._root = root.resolve()
        self._read_only = read_only
        if not read_only:
            try:
                self._root.mkdir(parents=True, exist_ok=True)
            except OSError as err:
                raise StorageError(f"Cannot create the store directory {self._root}: {err.strerror or err}.") from err

    @property
    def root(self) -> Path:
        """The resolved store directory."""
        return self._root

    def put_stream(self, key: str, stream: BinaryIO, *, length: int | None = None) -> ObjectInfo:
        """Copy ``stream`` into the object file via a temp file and rename."""
        path = self._writable_path(key)
        return ObjectInfo(key, write_atomically(path, stream, length=length))

    @contextmanager
    def open_read(self, key: str) -> Iterator[BinaryIO]:
        """Open the object file for streaming reads."""
        path = self._path(key)
        try:
            handle = path.open("rb")
        except (FileNotFoundError, NotADirectoryError, IsADirectoryError) as err:
            raise self._missing(key) from err
        except OSError as err:
            raise self._failed("read", key, err) from err
        with handle:
            yield handle

    def read_range(self, key: str, *, offset: int, length: int) -> bytes:
        """Read up to ``length`` bytes from ``offset``."""
        check_range(offset, length)
        with self.open_read(key) as handle:
            size = os.fstat(handle.fileno()).st_size
            handle.seek(offset)
            return handle.read(max(0, min(length, size - offset)))

    def download_to(self, key: str, path: Path) -> None:
        """Copy the object to ``path`` atomically."""
        with self.open_read(key) as handle:
            write_atomically(path, handle)

    def stat(self, key: str) -> ObjectInfo:
        """Size of the object; ObjectNotFoundError when there is no such file."""
        try:
            info = self._path(key).stat()
        except (FileNotFoundError, NotADirectoryError) as err:
            raise self._missing(key) from err
        except OSError as err:
            raise self._failed("stat", key, err) from err
        if not S_ISREG(info.st_mode):
            raise self._missing(key)
        return ObjectInfo(key, info.st_size)

    def exists(self, key: str) -> bool:
        """Whether a file is stored under ``key``."""
        return self._path(key).is_file()

    def delete(self, key: str) -> None:
        """Remove the object file if it exists."""
        path = self._writable_path(key)
        try:
            path.unlink(missing_ok=True)
        except (IsADirectoryError, NotADirectoryError):
            return
        except OSError as err:
            raise self._failed("delete", key, err) from err

    def list(self, prefix: str = "") -> Iterator[ObjectInfo]:
        """Objects under ``prefix``, sorted by key; temp files and foreign names are skipped."""
        start = self._root
        if validate_prefix(prefix):
            self._path(prefix[:-1])
            start = self._root.joinpath(*prefix[:-1].split("/"))
        return iter(sorted(self._walk(start), key=lambda info: info.key))

    def _walk(self, start: Path) -> Iterator[ObjectInfo]:
        for directory, _, files in os.walk(start):
            for name in files:
                info = self._describe(Path(directory, name))
                if info is not None:
                    yield info

    def _describe(self, path: Path) -> ObjectInfo | None:
        key = path.relative_to(self._root).as_posix()
        if not is_valid_key(key):
            return None
        try:
            resolved = path.resolve()
            info = resolved.stat()
        except OSError:
            return None
        if not resolved.is_relative_to(self._root) or not S_ISREG(info.st_mode):
            return None
        return ObjectInfo(key, info.st_size)

    def local_path(self, key: str) -> Path:
        """Where the object ``key`` lives on disk (validated to stay inside the store)."""
        return self._path(key)

    def _path(self, key: str) -> Path:
        try:
            resolved = self._root.joinpath(*validate_key(key).split("/")).resolve()
        except (OSError, RuntimeError) as err:  # RuntimeError: a symlink loop
            raise InvalidKeyError(f"Object key {key!r} does not resolve inside {self._root}: {err}.") from err
        if not resolved.is_relative_to(self._root):
            raise InvalidKeyError(f"Object key {key!r} resolves outside the store directory {self._root}.")
        return resolved

    def _writable_path(self, key: str) -> Path:
        path = self._path(key)
        if self._read_only:
            raise StorageError(f"The store at {self._root} is read-only; cannot write or delete {key!r}.")
        return path

    def _failed(self, action: str, key: str, err: OSError) -> StorageError:
        return StorageError(f"Cannot {action} object {key!r} in {self._root}: {err.strerror or err}.")

    def _missing(self, key: str) -> ObjectNotFoundError:
        return ObjectNotFoundError(f"No object under key {key!r} in {self._root}.")
