"""Rebuilding the catalog from storage: every bag stored with its registration (``catalog/<id>.json``) is
listed again with the same id, name and tags; a bag whose ingest finished (``indexes/<id>/summary.json``)
comes back ready with its summary and columnar index, any other is listed ingesting for the caller to queue.

Safe to run at any time and by several processes at once: bags already listed are left as they are, and a
registration whose files are gone (a delete cut short) is skipped with a note.
"""

from __future__ import annotations

import json
import logging
import time
from collections.abc import Callable
from dataclasses import dataclass, field

from bagmcp_shared import keys
from bagmcp_shared.catalog import BagRecord, Catalog, CatalogSummary
from bagmcp_shared.errors import NameTakenError, ObjectNotFoundError, StorageError
from bagmcp_shared.storage import ObjectStore

log = logging.getLogger(__name__)

RESTORE_WAIT_S = 120.0
FIRST_PAUSE_S = 0.5
LONGEST_PAUSE_S = 8.0


@dataclass
class Rebuilt:
    """What a rebuild listed: ``ready`` from their ingest summaries, ``to_ingest`` (the caller queues their
    ingest), and ``skipped`` with the reason for each."""

    ready: list[str] = field(default_factory=list)
    to_ingest: list[str] = field(default_factory=list)
    skipped: list[str] = field(default_factory=list)

    def __str__(self) -> str:
        return (
            f"listed {len(self.ready) + len(self.to_ingest)} bags again ({len(self.ready)} ready, "
            f"{len(self.to_ingest)} to ingest), skipped {len(self.skipped)}"
        )


def storage_has_bags(store: ObjectStore) -> bool:
    return next(iter(store.list(keys.REGISTRATIONS)), None) is not None


def _registration(store: ObjectStore, key: str) -> BagRecord:
    with store.open_read(key) as stream:
        return BagRecord.model_validate_json(stream.read())


def _ingested(store: ObjectStore, record: BagRecord) -> BagRecord | None:
    """The record as ingest left it (ready, summary, index files), or None when ingest never finished."""
    try:
        with store.open_read(keys.ingest_summary(record.id)) as stream:
            learned = json.loads(stream.read())
    except ObjectNotFoundError:
        return None
    summary = CatalogSummary.model_validate(learned["summary"])
    columns = keys.index_file(record.id, "")
    index_files = [info.key.removeprefix(columns) for info in store.list(columns)]
    return record.model_copy(update={"status": "ready", "summary": summary, "index_files": index_files})


def _claim_name(catalog: Catalog, record: BagRecord) -> BagRecord:
    """The record under its own name, or (taken by another bag meanwhile) its name with the id's start."""
    for name in (record.name, f"{record.name}-{record.id[:8]}"):
        try:
            catalog.claim_name(name, record.id)
            return record.model_copy(update={"name": name})
        except NameTakenError:
            continue
    raise NameTakenError(f"both {record.name!r} and {record.name}-{record.id[:8]!r} are taken")


def _relist(catalog: Catalog, store: ObjectStore, key: str, *, summaries: bool) -> tuple[BagRecord, bool] | None:
    """List one registration again; returns (record, ready) or None when it was listed already."""
    record = _registration(store, key)
    if catalog.get(record.id) is not None:
        return None
    stored = {info.key for info in store.list(f"{keys.bag_prefix(record.id)}/")}
    if missing := [name for name in record.files if keys.bag_file(record.id, name) not in stored]:
        raise ObjectNotFoundError(f"its files {', '.join(missing)} are missing from storage")
    again = {"status": "ingesting", "summary": None, "error": None, "progress": None, "ingest_queued_at": time.time()}
    fresh = record.model_copy(update=again)
    ingested = _ingested(store, record) if summaries else None
    named = _claim_name(catalog, ingested or fresh)
    if not catalog.add(named):  # listed by another process meanwhile
        catalog.release_name(named.name, named.id)
        return None
    return named, ingested is not None


def rebuild_catalog(catalog: Catalog, store: ObjectStore, *, summaries: bool = True) -> Rebuilt:
    """List again every stored bag the catalog lacks. ``summaries`` False lists them all for ingest (an
    embedded server, whose indexes live outside the store)."""
    rebuilt = Rebuilt()
    for info in store.list(keys.REGISTRATIONS):
        try:
            outcome = _relist(catalog, store, info.key, summaries=summaries)
        except (ObjectNotFoundError, NameTakenError, ValueError, KeyError) as err:  # storage outages propagate
            log.warning("not listing %s again: %s", info.key, err)
            rebuilt.skipped.append(f"{info.key}: {err}")
            continue
        if outcome is not None:
            record, ready = outcome
            (rebuilt.ready if ready else rebuilt.to_ingest).append(record.id)
    return rebuilt


def restore_lost_catalog(
    catalog: Catalog, store: ObjectStore, queue_ingest: Callable[[str], None], *, wait_s: float = 0.0
) -> Rebuilt | None:
    """At start-up: when the catalog is empty but storage holds bags (Redis lost its data), list them again
    and queue the ingest of those that never finished. None when there was nothing to restore. While the
    object store fails, tries again for up to ``wait_s`` (``_until_storage_answers``)."""
    if catalog.all():
        return None
    rebuilt = _until_storage_answers(
        lambda: rebuild_catalog(catalog, store) if storage_has_bags(store) else None, wait_s
    )
    if rebuilt is None:
        return None
    for bag_id in rebuilt.to_ingest:
        queue_ingest(bag_id)
    log.warning("the catalog was empty while storage holds bags: %s", rebuilt)
    return rebuilt


def _until_storage_answers(attempt: Callable[[], Rebuilt | None], wait_s: float) -> Rebuilt | None:
    """``attempt`` (safe to repeat: bags listed already are left as they are) tried again while the object store
    fails: an S3 server still starting answers the bucket check before it lists, and the restore crashed the
    bag-store, each crash counting toward the supervisor's restart limit. Pauses 0.5 s, doubling to 8 s, for
    up to ``wait_s``; one log line when it starts waiting, one when storage answered."""
    deadline = time.monotonic() + wait_s
    pause_s, waited = FIRST_PAUSE_S, False
    while True:
        try:
            outcome = attempt()
        except StorageError as err:
            if time.monotonic() + pause_s > deadline:
                raise
            if not waited:
                log.warning(
                    "the object store is not ready for the catalog check (%s); trying again for %.0f s", err, wait_s
                )
                waited = True
            time.sleep(pause_s)
            pause_s = min(pause_s * 2, LONGEST_PAUSE_S)
            continue
        if waited:
            log.warning("the object store answers; the catalog check is done")
        return outcome
