"""The bag-store's start-up catalog restore waits for an object store that does not answer yet (a real weed,
stopped, then started two seconds into the restore) and lists the lost bag again, with one log line for the
wait. Before, the restore raised StorageError: the bag-store crashed at start while S3 was still starting, and
each crash counted toward the stack supervisor's restart limit."""

from __future__ import annotations

import logging
import threading
import time
from pathlib import Path

import pytest

from bagmcp_bag_store.ingest import rebuild
from bagmcp_bag_store.ingest.rebuild import restore_lost_catalog
from bagmcp_shared import keys
from bagmcp_shared.catalog import MemoryCatalog
from bagmcp_shared.storage import S3Store
from tests.fixtures.faults import weed_server
from tests.fixtures.records import stored_record
from tests.fixtures.servers import remove_weed_sockets

pytestmark = pytest.mark.integration

BAG_ID = "0123456789abcdef0123456789abcdef"


def test_the_restore_waits_for_a_starting_object_store(
    tmp_path: Path, caplog: pytest.LogCaptureFixture, monkeypatch: pytest.MonkeyPatch
) -> None:
    # pauses of 0.5 s, then 1 s: the doubling up to 8 s overshot weed's start by up to 8 s (what the test checks
    # is the waiting, not the schedule)
    monkeypatch.setattr(rebuild, "LONGEST_PAUSE_S", 1.0)
    server, endpoint, ports = weed_server(tmp_path)
    try:
        server.start()
        store = S3Store(
            endpoint=endpoint.endpoint, access_key=endpoint.access_key, secret_key=endpoint.secret_key, bucket="restore"
        )
        store.ensure_bucket()
        record = stored_record(BAG_ID, "kept_in_storage")
        store.put_bytes(keys.registration(BAG_ID), record.model_dump_json().encode())
        store.put_bytes(keys.bag_file(BAG_ID, "kept_in_storage.bag"), b"bag bytes")
        server.stop()
        starter = threading.Timer(2.0, server.start)
        starter.start()
        queued: list[str] = []
        began = time.monotonic()
        with caplog.at_level(logging.WARNING, logger="bagmcp_bag_store.ingest.rebuild"):
            restored = restore_lost_catalog(MemoryCatalog(), store, queued.append, wait_s=60)
        starter.join()
        assert time.monotonic() - began >= 2
        assert restored is not None
        assert restored.to_ingest == [BAG_ID]
        assert queued == [BAG_ID]
        waiting = [r.message for r in caplog.records if "not ready for the catalog check" in r.message]
        assert len(waiting) == 1
    finally:
        server.stop()
        remove_weed_sockets(ports)
