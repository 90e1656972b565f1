"""The S3 server the tests start (as `make stack` starts it) can be administered only through S3 with its keys:
the master's HTTP admin endpoints answer nothing, the volume server refuses admin calls, and reads and writes
of a stored file, without a token signed by its keys, and every gRPC port asks for the stack's client
certificate. Before, ``GET /col/delete?collection=<bucket>`` on the master port deleted every object, and any
local gRPC client (``weed shell``) could do the same."""

from __future__ import annotations

import io
import secrets
import socket
import struct
import time
from pathlib import Path

import httpx
import jwt
import pytest
from minio import Minio

from tests.fixtures.servers import HTTP2_PREFACE, S3Endpoint, weed_grpc_refuses

pytestmark = pytest.mark.integration

BUCKET = "weed-admin-closed"
SETTINGS = b"\x00\x00\x00\x04\x00\x00\x00\x00\x00"


@pytest.fixture
def s3(s3_server: S3Endpoint) -> Minio:
    if not s3_server.master_port:
        pytest.skip("the S3 server runs in a container (MinIO), which has no weed admin ports")
    return Minio(s3_server.endpoint, access_key=s3_server.access_key, secret_key=s3_server.secret_key, secure=False)


def test_the_masters_collection_delete_is_refused_and_the_objects_stay(s3: Minio, s3_server: S3Endpoint) -> None:
    if not s3.bucket_exists(BUCKET):
        s3.make_bucket(BUCKET)
    s3.put_object(BUCKET, "bag/one.mcap", io.BytesIO(b"x" * 1000), 1000)
    master = f"http://127.0.0.1:{s3_server.master_port}"
    deleted = httpx.get(f"{master}/col/delete", params={"collection": BUCKET}, timeout=10)
    assert deleted.status_code == 404
    assert httpx.get(f"{master}/dir/status", timeout=10).status_code == 404
    assert s3.get_object(BUCKET, "bag/one.mcap").read() == b"x" * 1000


def test_the_volume_servers_admin_calls_need_the_stacks_key(s3: Minio, s3_server: S3Endpoint) -> None:
    volume = f"http://127.0.0.1:{s3_server.volume_port}"
    for path in ("/admin/delete_collection", "/admin/assign_volume"):
        refused = httpx.get(f"{volume}{path}", params={"collection": BUCKET, "volume": "99"}, timeout=10)
        assert refused.status_code == 401, path
        assert "jwt" in refused.text


def test_every_grpc_port_asks_for_the_stacks_client_certificate(s3: Minio, s3_server: S3Endpoint) -> None:
    assert len(s3_server.grpc_ports) == 4
    for port in s3_server.grpc_ports:
        assert weed_grpc_refuses(port) == "TLSV13_ALERT_CERTIFICATE_REQUIRED", port
        with socket.create_connection(("127.0.0.1", port), timeout=10) as plain:
            plain.sendall(HTTP2_PREFACE + SETTINGS)
            assert plain.recv(100) == b"", port  # no gRPC in plain text


def _file_id(s3_server: S3Endpoint, payload: bytes) -> str:
    """The volume server's file id (``vid,<key><cookie>``) of the needle holding ``payload``, read from its .dat
    files: the needle's header (cookie, key, size) sits just before its data size and data."""
    command = Path(f"/proc/{s3_server.pid}/cmdline").read_bytes().decode().split("\0")
    data_dir = Path(next(arg.split("=", 1)[1] for arg in command if arg.startswith("-dir=")))
    for dat in data_dir.glob("*.dat"):
        content = dat.read_bytes()
        at = content.find(payload)
        if at >= 0:
            cookie, key, _size, data_size = struct.unpack(">IQII", content[at - 20 : at])
            assert data_size == len(payload)
            return f"{dat.stem.rsplit('_', 1)[-1]},{key:x}{cookie:08x}"
    raise AssertionError(f"no volume in {data_dir} holds the object")


def test_the_volume_server_refuses_unsigned_reads_and_writes_of_a_stored_file(s3: Minio, s3_server: S3Endpoint) -> None:
    """The file id of an object just stored through S3: a GET or POST on it without a token signed by the
    stack's keys answers 401, and the object stays as it was."""
    if not s3.bucket_exists(BUCKET):
        s3.make_bucket(BUCKET)
    payload = secrets.token_bytes(4000)  # random, so weed stores it as sent (not gzipped)
    s3.put_object(BUCKET, "bag/read-me.mcap", io.BytesIO(payload), len(payload))
    fid = _file_id(s3_server, payload)
    url = f"http://127.0.0.1:{s3_server.volume_port}/{fid}"
    read = httpx.get(url, timeout=10)
    assert read.status_code == 401
    assert payload not in read.content
    assert "jwt" in read.text
    written = httpx.post(url, files={"file": ("x.mcap", b"overwritten")}, timeout=10)
    assert written.status_code == 401
    assert "jwt" in written.text
    assert s3.get_object(BUCKET, "bag/read-me.mcap").read() == payload
    environ = dict(v.split("=", 1) for v in Path(f"/proc/{s3_server.pid}/environ").read_text().split("\0") if "=" in v)
    signed = jwt.encode({"fid": fid, "exp": int(time.time()) + 60}, environ["WEED_JWT_SIGNING_READ_KEY"], "HS256")
    control = httpx.get(url, headers={"Authorization": f"Bearer {signed}"}, timeout=10)
    assert (control.status_code, control.content) == (200, payload)  # the id is real; only the token was missing
