"""LocalStore and S3Store against real storage: a weed S3 server, a directory, and our own redis-server."""

from __future__ import annotations

import hashlib
import io
import random
import secrets
import time
from collections.abc import Callable
from pathlib import Path
from typing import BinaryIO
from urllib.parse import urlsplit

import pytest
import redis
from minio import Minio

from bagmcp_shared.errors import InvalidKeyError, ObjectNotFoundError, StorageError
from bagmcp_shared.storage import LocalStore, ObjectInfo, ObjectStore, S3Store
from tests.fixtures.servers import S3Endpoint, free_port, using_docker

pytestmark = pytest.mark.integration  # fixtures come from tests.fixtures.servers via tests/conftest.py

SIZE = 20 * 1024 * 1024
RANGE_OFFSET, RANGE_LENGTH = 7_000_000, 1_000_000
HOSTILE_KEYS = ["../etc/passwd", "/abs", "a/../../b", "a\\b", "", "a//b"]


@pytest.fixture(scope="module")
def payload() -> bytes:
    """20 MiB of seeded random bytes: more than one 16 MiB multipart part."""
    return random.Random(20240601).randbytes(SIZE)


@pytest.fixture(scope="module")
def s3_store(s3_server: S3Endpoint) -> S3Store:
    store = S3Store(
        endpoint=s3_server.endpoint,
        access_key=s3_server.access_key,
        secret_key=s3_server.secret_key,
        bucket=f"objects-{secrets.token_hex(4)}",
    )
    store.ensure_bucket()
    store.ensure_bucket()  # a second call on an existing bucket is a no-op
    return store


@pytest.fixture(params=["local", "s3"])
def store(request: pytest.FixtureRequest, tmp_path: Path) -> ObjectStore:
    if request.param == "local":
        return LocalStore(tmp_path / "root")
    s3: S3Store = request.getfixturevalue("s3_store")
    return s3


def _prefix() -> str:
    return f"t{secrets.token_hex(6)}/"


def _sha256(stream: BinaryIO) -> str:
    digest = hashlib.sha256()
    while chunk := stream.read(1024 * 1024):
        digest.update(chunk)
    return digest.hexdigest()


def _round_trip(store: ObjectStore, key: str, payload: bytes) -> None:
    written = store.put_stream(key, io.BytesIO(payload), length=None)
    assert written == ObjectInfo(key, SIZE)
    assert store.stat(key) == ObjectInfo(key, SIZE)
    with store.open_read(key) as stream:
        assert _sha256(stream) == hashlib.sha256(payload).hexdigest()
    ranged = store.read_range(key, offset=RANGE_OFFSET, length=RANGE_LENGTH)
    assert ranged == payload[RANGE_OFFSET : RANGE_OFFSET + RANGE_LENGTH]
    assert store.read_range(key, offset=SIZE - 10, length=100) == payload[-10:]
    assert store.read_range(key, offset=SIZE - 10, length=1 << 40) == payload[-10:]  # no 1 TiB buffer
    assert store.read_range(key, offset=SIZE + 5, length=100) == b""
    assert store.read_range(key, offset=0, length=0) == b""


def test_a_20_mib_object_uploaded_with_unknown_length_round_trips_through_s3_as_multipart(
    s3_store: S3Store, s3_server: S3Endpoint, payload: bytes, tmp_path: Path
) -> None:
    key = f"{_prefix()}bags/big.mcap"
    _round_trip(s3_store, key, payload)
    client = Minio(s3_server.endpoint, access_key=s3_server.access_key, secret_key=s3_server.secret_key, secure=False)
    etag = client.stat_object(s3_store.bucket, key).etag
    assert etag is not None
    assert etag.endswith("-2")  # two parts: 16 MiB + 4 MiB
    target = tmp_path / "download" / "big.mcap"
    s3_store.download_to(key, target)
    assert hashlib.sha256(target.read_bytes()).hexdigest() == hashlib.sha256(payload).hexdigest()
    assert [p.name for p in target.parent.iterdir()] == ["big.mcap"]


def test_a_20_mib_object_round_trips_through_a_local_directory_with_exact_ranged_reads(
    payload: bytes, tmp_path: Path
) -> None:
    store = LocalStore(tmp_path / "root")
    _round_trip(store, "bags/big.mcap", payload)
    assert [p.relative_to(store.root).as_posix() for p in store.root.rglob("*")] == ["bags", "bags/big.mcap"]
    assert list(store.list()) == [ObjectInfo("bags/big.mcap", SIZE)]


def test_our_redis_server_round_trips_20_mib_and_is_not_the_system_redis(redis_url: str, payload: bytes) -> None:
    client = redis.Redis.from_url(redis_url)
    try:
        client.set("blob", payload)
        assert client.get("blob") == payload
        assert (
            client.getrange("blob", RANGE_OFFSET, RANGE_OFFSET + RANGE_LENGTH - 1)
            == payload[RANGE_OFFSET : RANGE_OFFSET + RANGE_LENGTH]
        )
        info = client.info("server")
    finally:
        client.close()
    port = urlsplit(redis_url).port
    if using_docker():
        assert info["tcp_port"] == 6379  # inside the container
    else:
        assert port != 6379
        assert info["tcp_port"] == port


@pytest.mark.parametrize("key", HOSTILE_KEYS)
def test_hostile_keys_are_rejected_by_every_operation_of_both_stores(
    store: ObjectStore, key: str, tmp_path: Path
) -> None:
    before = sorted(info.key for info in store.list())
    source = tmp_path / "source.bin"
    source.write_bytes(b"payload")
    operations: list[Callable[[], object]] = [
        lambda: store.put_bytes(key, b"x"),
        lambda: store.put_stream(key, io.BytesIO(b"x")),
        lambda: store.put_file(key, source),
        lambda: store.stat(key),
        lambda: store.exists(key),
        lambda: store.delete(key),
        lambda: store.read_range(key, offset=0, length=1),
        lambda: store.download_to(key, tmp_path / "out.bin"),
    ]
    for operation in operations:
        with pytest.raises(InvalidKeyError, match="is invalid"):
            operation()
    with pytest.raises(InvalidKeyError), store.open_read(key):
        pass
    assert sorted(info.key for info in store.list()) == before
    assert sorted(p.name for p in tmp_path.iterdir()) == (
        ["root", "source.bin"] if isinstance(store, LocalStore) else ["source.bin"]
    )


def test_a_local_store_never_follows_a_symlink_out_of_its_root(tmp_path: Path) -> None:
    outside = tmp_path / "outside"
    outside.mkdir()
    (outside / "secret").write_bytes(b"do not read")
    store = LocalStore(tmp_path / "root")
    (store.root / "link").symlink_to(outside, target_is_directory=True)
    (store.root / "file-link").symlink_to(outside / "secret")
    for key in ("link/secret", "link/new", "file-link"):
        with pytest.raises(InvalidKeyError, match="outside the store"):
            store.put_bytes(key, b"x")
        with pytest.raises(InvalidKeyError, match="outside the store"):
            store.stat(key)
    with pytest.raises(InvalidKeyError):
        list(store.list("link/"))
    assert list(store.list()) == []
    assert sorted(p.name for p in outside.iterdir()) == ["secret"]
    assert (outside / "secret").read_bytes() == b"do not read"


def test_missing_keys_raise_object_not_found_and_deleting_them_is_fine(store: ObjectStore, tmp_path: Path) -> None:
    key = f"{_prefix()}missing.bin"
    target = tmp_path / "target.bin"
    target.write_bytes(b"keep me")
    for operation in (
        lambda: store.stat(key),
        lambda: store.read_range(key, offset=0, length=10),
        lambda: store.read_range(key, offset=0, length=0),
        lambda: store.download_to(key, target),
    ):
        with pytest.raises(ObjectNotFoundError, match=r"missing\.bin"):
            operation()
    with pytest.raises(ObjectNotFoundError), store.open_read(key):
        pass
    assert store.exists(key) is False
    store.delete(key)
    assert target.read_bytes() == b"keep me"
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(
        ["target.bin", *(["root"] if isinstance(store, LocalStore) else [])]
    )


def test_a_key_that_is_only_a_directory_of_other_keys_is_not_an_object(store: ObjectStore) -> None:
    prefix = _prefix()
    store.put_bytes(f"{prefix}dir/file", b"abc")
    assert store.exists(f"{prefix}dir") is False
    with pytest.raises(ObjectNotFoundError):
        store.stat(f"{prefix}dir")
    store.delete(f"{prefix}dir")
    assert store.stat(f"{prefix}dir/file") == ObjectInfo(f"{prefix}dir/file", 3)


def test_listing_returns_every_object_under_a_prefix_sorted_by_key(store: ObjectStore) -> None:
    prefix = _prefix()
    names = ["b/c/d", "a0", "a/b", "a.x", "A", "a-b", "z"]
    for size, name in enumerate(names):
        store.put_bytes(prefix + name, bytes(size))
    store.put_bytes(f"{_prefix()}elsewhere", b"other prefix")
    listed = list(store.list(prefix))
    assert [info.key for info in listed] == sorted(prefix + name for name in names)
    assert {info.key: info.size for info in listed} == {prefix + name: size for size, name in enumerate(names)}
    assert list(store.list(f"{prefix}a/")) == [ObjectInfo(f"{prefix}a/b", 2)]
    assert list(store.list(f"{prefix}nothing/")) == []
    store.delete(f"{prefix}a/b")
    assert f"{prefix}a/b" not in [info.key for info in store.list(prefix)]


def test_put_file_and_put_bytes_overwrite_atomically(store: ObjectStore, tmp_path: Path) -> None:
    key = f"{_prefix()}file.bin"
    source = tmp_path / "source.bin"
    source.write_bytes(b"from a file")
    assert store.put_bytes(key, b"first version") == ObjectInfo(key, 13)
    assert store.put_file(key, source) == ObjectInfo(key, 11)
    with store.open_read(key) as stream:
        assert stream.read() == b"from a file"
    with pytest.raises(StorageError, match=r"ended after 3 of the promised 10 bytes|not enough data"):
        store.put_stream(key, io.BytesIO(b"abc"), length=10)
    assert store.read_range(key, offset=5, length=100) == b"a file"


def test_a_read_only_local_store_refuses_every_write(tmp_path: Path) -> None:
    LocalStore(tmp_path / "root").put_bytes("bags/kept.bin", b"original")
    store = LocalStore(tmp_path / "root", read_only=True)
    source = tmp_path / "source.bin"
    source.write_bytes(b"new")
    for operation in (
        lambda: store.put_bytes("bags/kept.bin", b"changed"),
        lambda: store.put_bytes("bags/new.bin", b"new"),
        lambda: store.put_stream("bags/new.bin", io.BytesIO(b"new")),
        lambda: store.put_file("bags/new.bin", source),
        lambda: store.delete("bags/kept.bin"),
    ):
        with pytest.raises(StorageError, match="read-only"):
            operation()
    assert list(store.list()) == [ObjectInfo("bags/kept.bin", 8)]
    assert store.read_range("bags/kept.bin", offset=0, length=100) == b"original"


def test_an_s3_store_without_a_server_fails_fast_with_a_storage_error_naming_the_endpoint() -> None:
    port = free_port()
    store = S3Store(endpoint=f"127.0.0.1:{port}", access_key="nobody", secret_key="nothing-here", bucket="absent")
    for operation in (store.ensure_bucket, lambda: store.put_bytes("k", b"x"), lambda: store.stat("k")):
        started = time.monotonic()
        with pytest.raises(StorageError) as caught:
            operation()
        elapsed = time.monotonic() - started
        assert elapsed < 10
        assert not isinstance(caught.value, ObjectNotFoundError)
        assert f"object store at http://127.0.0.1:{port} is unreachable" in str(caught.value)


def test_s3_credentials_the_server_does_not_know_are_refused_as_a_storage_error(
    s3_server: S3Endpoint,
) -> None:
    store = S3Store(endpoint=s3_server.endpoint, access_key="AKUNKNOWN", secret_key="wrong-secret", bucket="absent")
    with pytest.raises(StorageError, match=f"object store at http://{s3_server.endpoint} refused"):
        store.ensure_bucket()
