"""The benchmark's S3 delay proxy (bench/delay_proxy.py) in front of a real weed S3: every request waits the
delay once (not once per packet), the bytes pass intact both ways, and the counts are what went through."""

from __future__ import annotations

import hashlib
import io
import os
import time
from collections.abc import Callable, Iterator

import pytest
from minio import Minio

from bench.delay_proxy import DelayProxy, delay_proxy
from tests.fixtures.servers import S3Endpoint

pytestmark = pytest.mark.integration

DELAY_S = 0.02
BODY = os.urandom(3 * 2**20 + 17)  # more than one read of the proxy, not a multiple of it


@pytest.fixture
def proxied(s3_server: S3Endpoint) -> Iterator[tuple[DelayProxy, Minio]]:
    with delay_proxy(s3_server.endpoint) as proxy:
        client = Minio(proxy.endpoint, access_key=s3_server.access_key, secret_key=s3_server.secret_key, secure=False)
        bucket = f"proxy-{proxy.port}"
        client.make_bucket(bucket)
        client.put_object(bucket, "body", io.BytesIO(BODY), len(BODY))
        yield proxy, client


def _bucket(proxy: DelayProxy) -> str:
    return f"proxy-{proxy.port}"


def _median_s(run: Callable[[], None], times: int = 7) -> float:
    took = []
    for _ in range(times):
        began = time.perf_counter()
        run()
        took.append(time.perf_counter() - began)
    return sorted(took)[times // 2]


def test_bytes_pass_intact_both_ways_and_are_counted(proxied: tuple[DelayProxy, Minio]) -> None:
    proxy, client = proxied
    before = proxy.counts()
    whole = client.get_object(_bucket(proxy), "body").read()
    ranged = client.get_object(_bucket(proxy), "body", offset=2**20 + 5, length=70_000).read()
    counted = proxy.counts() - before
    assert hashlib.sha256(whole).digest() == hashlib.sha256(BODY).digest()
    assert ranged == BODY[2**20 + 5 : 2**20 + 5 + 70_000]
    assert len(BODY) + 70_000 < counted.answered_bytes < len(BODY) + 70_000 + 8_000  # bodies and headers
    assert counted.requests == 2
    assert list(proxy.recent)[-2:] == [
        f"GET /{_bucket(proxy)}/body",
        f"GET /{_bucket(proxy)}/body bytes={2**20 + 5}-{2**20 + 5 + 70_000 - 1}",
    ]
    assert 0 < counted.sent_bytes < 4_000  # two signed GETs


def test_every_request_waits_the_delay_once(proxied: tuple[DelayProxy, Minio]) -> None:
    proxy, client = proxied

    def small_read() -> None:
        client.get_object(_bucket(proxy), "body", offset=0, length=100).read()

    def whole_upload() -> None:  # one request whose body crosses the proxy in many reads
        client.put_object(_bucket(proxy), "again", io.BytesIO(BODY), len(BODY))

    small_read()  # a kept-alive connection
    plain_read, plain_upload = _median_s(small_read), _median_s(whole_upload, 3)
    proxy.delay_s = DELAY_S
    before = proxy.counts()
    delayed_read, delayed_upload = _median_s(small_read), _median_s(whole_upload, 3)
    assert (proxy.counts() - before).requests == 10
    assert DELAY_S * 0.9 < delayed_read - plain_read < DELAY_S * 2.5
    assert delayed_upload - plain_upload < DELAY_S * 2.5  # one delay for the request, none per body read
