"""Uploading a bag again: a duplicate of a healthy bag changes nothing, a failed or stuck one is queued again."""

from __future__ import annotations

import hashlib
import shutil
import time
from pathlib import Path

from bagmcp_bag_store.ingest.shelf import Shelf
from bagmcp_bag_store.ingest.upload import Received, UploadPolicy, store_upload
from bagmcp_shared.catalog import MemoryCatalog
from bagmcp_shared.storage import LocalStore
from tests.fixtures.bagfactory import BagKind


def _received(bag: Path, scratch: Path) -> Received:
    body = scratch / f"body-{time.monotonic_ns()}"
    shutil.copyfile(bag, body)
    return Received(body, body.stat().st_size, hashlib.sha256(body.read_bytes()).hexdigest())


def test_a_failed_or_stuck_bag_uploaded_again_is_queued_again_and_a_healthy_one_is_not(
    tmp_path: Path, scenario_bags: dict[BagKind, Path]
) -> None:
    catalog, queued = MemoryCatalog(), list[str]()
    policy = UploadPolicy(
        Shelf(catalog, LocalStore(tmp_path / "objects")), queued.append, tmp_path, max_bytes=1 << 30, stuck_after_s=60
    )
    bag = scenario_bags["ros1"]

    def upload() -> str:
        stored = store_upload(policy, _received(bag, tmp_path), filename="run.bag", name=None, tags=[])
        return stored.record.id

    bag_id = upload()
    assert queued == [bag_id]
    upload()  # still ingesting, queued a moment ago: its worker has it
    assert queued == [bag_id]
    record = catalog.get(bag_id)
    assert record is not None
    catalog.replace(record.model_copy(update={"status": "failed", "error": "storage was unavailable"}))
    upload()
    assert queued == [bag_id, bag_id]
    again = catalog.get(bag_id)
    assert again is not None
    assert (again.status, again.error) == ("ingesting", None)
    catalog.replace(again.model_copy(update={"ingest_queued_at": time.time() - 61}))  # its worker died
    upload()
    assert queued == [bag_id, bag_id, bag_id]
    done = catalog.get(bag_id)
    assert done is not None
    catalog.replace(done.model_copy(update={"status": "ready"}))
    upload()
    assert queued == [bag_id, bag_id, bag_id]
    assert [p.name for p in tmp_path.iterdir() if p.name != "objects"] == []  # bodies and staging removed
