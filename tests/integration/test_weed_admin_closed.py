"""The S3 server the tests start (as `make stack` starts it) can be administered only through S3 with its keys:
the master's HTTP admin endpoints answer nothing, the volume server refuses admin calls without a token signed
by its key, and every gRPC port asks for the stack's client certificate. Before, ``GET
/col/delete?collection=<bucket>`` on the master port deleted every object, and any local gRPC client (``weed
shell``) could do the same."""

from __future__ import annotations

import io
import socket

import httpx
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
