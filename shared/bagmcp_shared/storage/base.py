"""The object store contract shared by every backend, plus key validation and atomic file writes."""

from __future__ import annotations

import io
import os
import re
import tempfile
from collections.abc import Iterator
from contextlib import AbstractContextManager, suppress
from dataclasses import dataclass, field
from pathlib import Path
from typing import BinaryIO, NamedTuple, Protocol

from bagmcp_shared.errors import InvalidKeyError, StorageError

MAX_KEY_LENGTH = 1024
COPY_CHUNK = 1024 * 1024
TEMP_PREFIX = ".tmp-"
_SEGMENT = re.compile(r"[A-Za-z0-9][A-Za-z0-9._-]*")
_KEY_RULE = (
    "keys are relative, '/'-separated paths of at most 1024 characters whose segments start with "
    "a letter or digit and contain only letters, digits, '.', '_' and '-'"
)


@dataclass(frozen=True)
class ObjectInfo:
    """One stored object: its key, its size in bytes and (where the store has one) its ETag."""

    key: str
    size: int
    etag: str = field(default="", compare=False)  # equal objects are equal by key and size


class RangeAnswer(NamedTuple):
    """A ranged read's bytes with what the server said of the whole object: its ETag ("" when it sent none)
    and its size in bytes (from ``Content-Range``; UNKNOWN_TOTAL when it sent none)."""

    data: bytes
    etag: str
    total: int


UNKNOWN_TOTAL = -1


class ObjectStore(Protocol):
    """A flat key -> bytes store (a directory or an S3 bucket)."""

    def put_stream(self, key: str, stream: BinaryIO, *, length: int | None = None) -> ObjectInfo:
        """Store ``stream`` under ``key`` with bounded memory; ``length`` None means unknown."""
        ...

    def put_file(self, key: str, path: Path) -> ObjectInfo:
        """Store the local file ``path`` under ``key``."""
        ...

    def put_bytes(self, key: str, data: bytes) -> ObjectInfo:
        """Store ``data`` under ``key``."""
        ...

    def open_read(self, key: str) -> AbstractContextManager[BinaryIO]:
        """Stream the whole object; the stream is closed when the context exits."""
        ...

    def read_range(self, key: str, *, offset: int, length: int) -> bytes:
        """Read up to ``length`` bytes from ``offset``; a range past the end returns what exists."""
        ...

    def download_to(self, key: str, path: Path) -> None:
        """Copy the object to ``path`` atomically (temp file beside it, then rename)."""
        ...

    def stat(self, key: str) -> ObjectInfo:
        """Describe the object; raises ObjectNotFoundError when it is missing."""
        ...

    def exists(self, key: str) -> bool:
        """Whether an object is stored under ``key``."""
        ...

    def delete(self, key: str) -> None:
        """Remove the object; a missing key is not an error."""
        ...

    def list(self, prefix: str = "") -> Iterator[ObjectInfo]:
        """Every object under ``prefix`` ("" or ending in '/'), recursively, sorted by key."""
        ...


def validate_key(key: str) -> str:
    """Return ``key`` unchanged if it is a safe object key, else raise InvalidKeyError."""
    if not isinstance(key, str) or not is_valid_key(key):
        raise InvalidKeyError(f"Object key {key!r} is invalid: {_KEY_RULE}.")
    return key


def validate_prefix(prefix: str) -> str:
    """Return ``prefix`` if it is "" or a valid key followed by '/', else raise InvalidKeyError."""
    if prefix == "" or (isinstance(prefix, str) and prefix.endswith("/") and is_valid_key(prefix[:-1])):
        return prefix
    raise InvalidKeyError(f"Listing prefix {prefix!r} is invalid: use '' or a valid key followed by '/'; {_KEY_RULE}.")


def is_valid_key(key: str) -> bool:
    """Whether ``key`` passes validate_key (used to skip foreign or temporary names)."""
    if not key or len(key) > MAX_KEY_LENGTH:
        return False
    return all(_SEGMENT.fullmatch(segment) for segment in key.split("/"))


def check_range(offset: int, length: int) -> None:
    """Reject negative offsets and lengths."""
    if offset < 0 or length < 0:
        raise StorageError(f"A byte range needs offset >= 0 and length >= 0, got offset={offset}, length={length}.")


def write_atomically(path: Path, stream: BinaryIO, *, length: int | None = None) -> int:
    """Copy ``stream`` into a temp file beside ``path``, then rename it over ``path``; return the size."""
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, temp_name = tempfile.mkstemp(prefix=TEMP_PREFIX, dir=path.parent)
    except OSError as err:
        raise StorageError(f"Cannot write {path}: {err.strerror or err}.") from err
    temp = Path(temp_name)
    try:
        with os.fdopen(fd, "wb") as out:
            size = _copy(stream, out, length)
            out.flush()
            os.fsync(out.fileno())
        temp.replace(path)
    except BaseException as err:
        with suppress(OSError):
            temp.unlink()
        if isinstance(err, OSError):
            raise StorageError(f"Cannot write {path}: {err.strerror or err}.") from err
        raise
    return size


def _copy(stream: BinaryIO, out: BinaryIO, length: int | None) -> int:
    copied = 0
    while length is None or copied < length:
        chunk = stream.read(COPY_CHUNK if length is None else min(COPY_CHUNK, length - copied))
        if not chunk:
            break
        out.write(chunk)
        copied += len(chunk)
    if length is not None and copied < length:
        raise StorageError(f"The stream ended after {copied} of the promised {length} bytes.")
    return copied


def open_local_file(path: Path) -> BinaryIO:
    """Open a local source file for upload, turning OS errors into StorageError."""
    try:
        return path.open("rb")
    except OSError as err:
        raise StorageError(f"Cannot read local file {path}: {err.strerror or err}.") from err


class StreamPutters:
    """``put_file`` and ``put_bytes`` for any store that implements ``put_stream``."""

    def put_stream(self, key: str, stream: BinaryIO, *, length: int | None = None) -> ObjectInfo:
        raise NotImplementedError

    def put_file(self, key: str, path: Path) -> ObjectInfo:
        """Store the local file ``path`` under ``key``."""
        validate_key(key)
        with open_local_file(path) as source:
            return self.put_stream(key, source, length=os.fstat(source.fileno()).st_size)

    def put_bytes(self, key: str, data: bytes) -> ObjectInfo:
        """Store ``data`` under ``key``."""
        return self.put_stream(key, io.BytesIO(data), length=len(data))
