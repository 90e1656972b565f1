"""Ingest: read a stored bag once and record what later questions need in the catalog."""

from __future__ import annotations

import json
import logging
import tempfile
from pathlib import Path

from pydantic import JsonValue

from bagmcp_bag_store.deps import BagStoreDeps
from bagmcp_bag_store.errors import BagNotFoundError
from bagmcp_shared.bags import open_bag
from bagmcp_shared.bags.report import summary_dict
from bagmcp_shared.columns import build_index
from bagmcp_shared.errors import BagError

log = logging.getLogger(__name__)


def _definitions(connections: list[tuple[str, str, str]]) -> dict[str, JsonValue]:
    return {msgtype: {"format": fmt, "text": text} for msgtype, fmt, text in connections}


def ingest_bag(deps: BagStoreDeps, bag_id: str) -> str:
    """Summarize the bag, build its columnar index, and mark it ready (or failed, with the reason).

    Idempotent: a redelivered task on a ready bag does nothing.
    """
    record = deps.catalog.get(bag_id)
    if record is None:
        raise BagNotFoundError(f"bag {bag_id} is not in the catalog (deleted while queued?)")
    if record.status == "ready":
        return record.status
    try:
        with (
            open_bag(deps.files.path_for(record)) as bag,
            tempfile.TemporaryDirectory(prefix="bagmcp-index-") as tmp,
        ):
            summary: dict[str, JsonValue] = json.loads(json.dumps(summary_dict(bag.summary())))
            definitions = _definitions([(c.msgtype, c.definition_format, c.definition) for c in bag.connections])
            build_index(bag, Path(tmp) / "columns")
            index_files = deps.files.publish_index(record, Path(tmp) / "columns")
    except BagError as err:
        log.warning("ingest of %s failed: %s", bag_id, err)
        deps.catalog.put(record.model_copy(update={"status": "failed", "error": str(err)}))
        return "failed"
    summary["path"] = record.name
    if deps.store is not None:
        index = {"summary": summary, "definitions": definitions}
        deps.store.put_bytes(f"indexes/{bag_id}/summary.json", json.dumps(index).encode())
    ready = {"status": "ready", "summary": summary, "error": None, "index_files": index_files}
    deps.catalog.put(record.model_copy(update=ready))
    return "ready"
