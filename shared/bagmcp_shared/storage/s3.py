"""S3Store: objects in one bucket of an S3-compatible server, through the minio client."""

from __future__ import annotations

import io
from collections.abc import Iterator
from contextlib import contextmanager
from functools import partial
from pathlib import Path
from typing import TYPE_CHECKING, BinaryIO

import certifi
import urllib3
from minio import Minio
from minio.error import MinioException, S3Error
from minio.helpers import check_bucket_name
from urllib3.exceptions import ConnectTimeoutError, HTTPError, MaxRetryError
from urllib3.util import Retry, Timeout

from bagmcp_shared.errors import ObjectNotFoundError, StorageError
from bagmcp_shared.storage.base import (
    UNKNOWN_TOTAL,
    ObjectInfo,
    RangeAnswer,
    StreamPutters,
    check_range,
    is_valid_key,
    validate_key,
    validate_prefix,
    write_atomically,
)

if TYPE_CHECKING:
    from _typeshed import WriteableBuffer
    from urllib3 import BaseHTTPResponse

PART_SIZE = 16 * 1024 * 1024
CONNECT_TIMEOUT_S = 3.0
READ_TIMEOUT_S = 60.0
PROBE_TIMEOUT_S = 3.0
_MISSING_CODES = frozenset({"NoSuchKey", "NoSuchObject"})
_TRANSPORT_ERRORS = (HTTPError, MinioException)


def _http_client(read_timeout_s: float, ca_file: str | None) -> urllib3.PoolManager:
    """A pool that gives up on an unreachable server within seconds (minio's default waits minutes)."""
    return urllib3.PoolManager(
        timeout=Timeout(connect=CONNECT_TIMEOUT_S, read=read_timeout_s),
        retries=Retry(total=3, connect=1, read=1, backoff_factor=0.2, status_forcelist=(500, 502, 503, 504)),
        maxsize=10,
        cert_reqs="CERT_REQUIRED",
        ca_certs=ca_file or certifi.where(),
    )


def _probe_client(ca_file: str | None) -> urllib3.PoolManager:
    """For ``S3Store.answers``: one try, seconds at most (a frozen server must not hold /readyz)."""
    return urllib3.PoolManager(
        timeout=Timeout(connect=PROBE_TIMEOUT_S, read=PROBE_TIMEOUT_S),
        retries=False,
        maxsize=2,
        cert_reqs="CERT_REQUIRED",
        ca_certs=ca_file or certifi.where(),
    )


class S3Store(StreamPutters):
    """Keys are object names in ``bucket``; every client failure surfaces as a StorageError."""

    def __init__(
        self,
        *,
        endpoint: str,
        access_key: str,
        secret_key: str,
        bucket: str,
        secure: bool = False,
        region: str | None = None,
        read_timeout_s: float = READ_TIMEOUT_S,
        ca_file: str | None = None,
    ) -> None:
        """``ca_file``: the certificate authorities to trust for ``secure`` (default: certifi's)."""
        self._url = f"{'https' if secure else 'http'}://{endpoint}"
        self._bucket = bucket
        try:
            check_bucket_name(bucket)
            client = partial(
                Minio, endpoint, access_key=access_key, secret_key=secret_key, secure=secure, region=region
            )
            self._client = client(http_client=_http_client(read_timeout_s, ca_file))
            self._probe = client(http_client=_probe_client(ca_file))
        except ValueError as err:
            raise StorageError(f"Cannot use bucket {bucket!r} at {self._url}: {err}.") from err

    @property
    def bucket(self) -> str:
        """The bucket holding every object of this store."""
        return self._bucket

    def answers(self) -> bool:
        """Whether the server answers an authenticated look at the bucket within 3 s, in one try (for
        /readyz: the bag-store answers its tools while S3 is down)."""
        try:
            return bool(self._probe.bucket_exists(self._bucket))
        except (*_TRANSPORT_ERRORS, ValueError):
            return False

    def ensure_bucket(self) -> None:
        """Create the bucket unless it already exists."""
        with self._guard("create the bucket"):
            if self._client.bucket_exists(self._bucket):
                return
            try:
                self._client.make_bucket(self._bucket)
            except S3Error as err:
                if err.code not in ("BucketAlreadyOwnedByYou", "BucketAlreadyExists"):
                    raise

    def put_stream(self, key: str, stream: BinaryIO, *, length: int | None = None) -> ObjectInfo:
        """Upload ``stream``; unknown length uses multipart with 16 MiB parts."""
        validate_key(key)
        with self._guard(f"store {key!r}"):
            try:
                written = self._client.put_object(
                    self._bucket, key, stream, -1 if length is None else length, part_size=PART_SIZE
                )
            except OSError as err:
                raise StorageError(f"Cannot upload {key!r} to {self._url}/{self._bucket}: {err}.") from err
        if length is None:
            return self.stat(key)
        return ObjectInfo(key, length, (written.etag or "").strip('"'))

    @contextmanager
    def open_read(self, key: str) -> Iterator[BinaryIO]:
        """Stream the object; the HTTP connection is released when the context exits."""
        validate_key(key)
        with self._guard(f"read {key!r}", key):
            response = self._client.get_object(self._bucket, key)
        try:
            with io.BufferedReader(_ResponseReader(response, self._url), buffer_size=1024 * 1024) as reader:
                yield reader
        finally:
            response.close()
            response.release_conn()

    def read_range(self, key: str, *, offset: int, length: int) -> bytes:
        """Ranged GET; an offset at or past the end gives b""."""
        validate_key(key)
        check_range(offset, length)
        if length == 0:
            self.stat(key)
            return b""
        with self._guard(f"read {key!r}", key):
            try:
                response = self._client.get_object(self._bucket, key, offset=offset, length=length)
            except S3Error as err:
                if err.code == "InvalidRange":
                    return b""
                raise
            try:
                return response.read()
            finally:
                response.close()
                response.release_conn()

    def read_range_tagged(self, key: str, *, offset: int, length: int) -> RangeAnswer:
        """Ranged GET of ``length`` > 0 bytes, with the ETag and the object's size the server sent along (so a
        caller that knows what the object should be sees a replaced one in the same request, with no HEAD)."""
        validate_key(key)
        check_range(offset, length)
        with self._guard(f"read {key!r}", key):
            response = self._client.get_object(self._bucket, key, offset=offset, length=max(length, 1))
            try:
                etag = (response.headers.get("ETag") or "").strip('"')
                return RangeAnswer(response.read(), etag, range_total(response.headers.get("Content-Range")))
            finally:
                response.close()
                response.release_conn()

    def download_to(self, key: str, path: Path) -> None:
        """Stream the object into ``path`` atomically."""
        with self.open_read(key) as source:
            write_atomically(path, source)

    def stat(self, key: str) -> ObjectInfo:
        """HEAD the object; ObjectNotFoundError when it is missing."""
        validate_key(key)
        with self._guard(f"stat {key!r}", key):
            found = self._client.stat_object(self._bucket, key)
        return ObjectInfo(key, found.size or 0, (found.etag or "").strip('"'))

    def exists(self, key: str) -> bool:
        """Whether the bucket holds ``key``."""
        try:
            self.stat(key)
        except ObjectNotFoundError:
            return False
        return True

    def delete(self, key: str) -> None:
        """Delete the object; S3 treats a missing key as success."""
        validate_key(key)
        with self._guard(f"delete {key!r}"):
            self._client.remove_object(self._bucket, key)

    def list(self, prefix: str = "") -> Iterator[ObjectInfo]:
        """Objects under ``prefix``, sorted by key; names that are not valid keys are skipped."""
        validate_prefix(prefix)
        with self._guard(f"list {prefix!r}"):
            found = [
                ObjectInfo(obj.object_name, obj.size or 0)
                for obj in self._client.list_objects(self._bucket, prefix=prefix or None, recursive=True)
                if obj.object_name is not None and is_valid_key(obj.object_name)
            ]
        return iter(sorted(found, key=lambda info: info.key))

    @contextmanager
    def _guard(self, action: str, key: str | None = None) -> Iterator[None]:
        try:
            yield
        except S3Error as err:
            if key is not None and err.code in _MISSING_CODES:
                raise ObjectNotFoundError(f"No object under key {key!r} in bucket {self._bucket!r}.") from err
            raise StorageError(
                f"The object store at {self._url} refused to {action} in bucket {self._bucket!r}: "
                f"{err.code}: {err.message}."
            ) from err
        except _TRANSPORT_ERRORS as err:
            raise transport_error(self._url, err) from err


def transport_error(url: str, err: Exception) -> StorageError:
    """A StorageError for a failed exchange; connection failures name the endpoint as unreachable."""
    reason = err.reason if isinstance(err, MaxRetryError) and err.reason is not None else err
    if isinstance(reason, ConnectTimeoutError):
        return StorageError(
            f"The object store at {url} is unreachable ({reason}); check that it runs and listens there."
        )
    return StorageError(f"The object store at {url} failed: {reason}.")


class _ResponseReader(io.RawIOBase):
    """A raw stream over a urllib3 response that reports failures as StorageError."""

    def __init__(self, response: BaseHTTPResponse, url: str) -> None:
        super().__init__()
        self._response = response
        self._url = url

    def readable(self) -> bool:
        return True

    def readinto(self, buffer: WriteableBuffer) -> int:
        view = memoryview(buffer).cast("B")
        try:
            data = self._response.read(len(view))
        except HTTPError as err:
            raise transport_error(self._url, err) from err
        view[: len(data)] = data
        return len(data)


def range_total(content_range: str | None) -> int:
    """The object's size from a ``Content-Range: bytes a-b/total`` header; UNKNOWN_TOTAL when absent or ``*``."""
    total = (content_range or "").rpartition("/")[2].strip()
    return int(total) if total.isdigit() else UNKNOWN_TOTAL
