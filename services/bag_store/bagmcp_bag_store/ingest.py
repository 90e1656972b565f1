"""Ingest: read a stored bag once and record what later questions need in the catalog."""

from __future__ import annotations

import json
import logging
import tempfile
from pathlib import Path

from pydantic import JsonValue

from bagmcp_bag_store.deps import BagStoreDeps
from bagmcp_bag_store.errors import BagNotFoundError
from bagmcp_bag_store.models import BagRecord
from bagmcp_shared.bags import BagReader, open_bag
from bagmcp_shared.bags.report import summary_dict
from bagmcp_shared.columns import ColumnIndex, build_index
from bagmcp_shared.errors import BagError

log = logging.getLogger(__name__)


def _definitions(bag: BagReader) -> dict[str, JsonValue]:
    return {c.msgtype: {"format": c.definition_format, "text": c.definition} for c in bag.connections}


def _index(deps: BagStoreDeps, record: BagRecord, bag: BagReader) -> tuple[list[str], dict[str, float]]:
    """The bag's columnar index (reused when this process already has a usable one, else built),
    and the header-stamp rate of each indexed topic that has sane header stamps."""
    if (existing := ColumnIndex.load(deps.files.index_dir(record))) is not None:
        return record.index_files, existing.header_rates()
    with tempfile.TemporaryDirectory(prefix="bagmcp-index-") as tmp:
        build_index(bag, Path(tmp) / "columns")
        built = ColumnIndex.load(Path(tmp) / "columns")
        assert built is not None
        return deps.files.publish_index(record, Path(tmp) / "columns"), built.header_rates()


def _with_header_rates(summary: dict[str, JsonValue], rates: dict[str, float]) -> None:
    topics = summary.get("topics")
    for topic in topics if isinstance(topics, list) else []:
        if isinstance(topic, dict):
            topic["header_rate_hz"] = rates.get(str(topic.get("name")))


def mark_failed(deps: BagStoreDeps, bag_id: str, reason: str) -> None:
    """Record why a bag cannot be used (no-op if it was deleted meanwhile)."""
    record = deps.catalog.get(bag_id)
    if record is not None:
        deps.catalog.replace(record.model_copy(update={"status": "failed", "error": reason}))


def ingest_bag(deps: BagStoreDeps, bag_id: str) -> str:
    """Summarize the bag, build its columnar index, and mark it ready (or failed, with the reason).

    Idempotent: a redelivered task on a ready bag does nothing. Storage errors propagate so the
    caller can retry; a bag deleted while ingesting stays deleted.
    """
    record = deps.catalog.get(bag_id)
    if record is None:
        raise BagNotFoundError(f"bag {bag_id} is not in the catalog (deleted while queued?)")
    if record.status == "ready":
        return record.status
    path = deps.files.path_for(record)
    try:
        with open_bag(path) as bag:
            summary: dict[str, JsonValue] = json.loads(json.dumps(summary_dict(bag.summary())))
            definitions = _definitions(bag)
            index_files, header_rates = _index(deps, record, bag)
    except BagError as err:
        reason = str(err).replace(str(path), record.name)  # no server paths in what clients see
        log.warning("ingest of %s failed: %s", bag_id, reason)
        mark_failed(deps, bag_id, reason)
        return "failed"
    summary["path"] = record.name
    _with_header_rates(summary, header_rates)
    if deps.store is not None and record.in_store:
        index = {"summary": summary, "definitions": definitions}
        deps.store.put_bytes(f"indexes/{bag_id}/summary.json", json.dumps(index).encode())
    ready = {"status": "ready", "summary": summary, "error": None, "index_files": index_files}
    if not deps.catalog.replace(record.model_copy(update=ready)):
        log.info("bag %s was deleted while it was ingested", bag_id)
        return "deleted"
    return "ready"
