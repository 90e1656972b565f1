"""Resolving what a caller calls a bag: an id, a name, or (for reading) a unique prefix of either."""

from __future__ import annotations

import difflib

from bagmcp_shared.catalog.models import BagRecord
from bagmcp_shared.catalog.protocol import Catalog
from bagmcp_shared.errors import AmbiguousBagError, BagNotFoundError, BagNotReadyError


def _not_found(ref: str, records: list[BagRecord]) -> BagNotFoundError:
    close = difflib.get_close_matches(ref, [r.name for r in records], n=5, cutoff=0.4)
    hint = f"; did you mean: {', '.join(close)}?" if close else ""
    known = "" if close else f"; {len(records)} bags exist (call list_bags)"
    return BagNotFoundError(f"no bag called {ref!r}{hint}{known}")


def exact_bag(catalog: Catalog, ref: str) -> BagRecord:
    """A bag by its exact id or name, for destructive calls (a prefix never deletes a bag)."""
    ref = ref.strip()
    if (record := catalog.get(ref) or catalog.named(ref)) is not None:
        return record
    records = catalog.all()
    found = next((r for r in records if r.name == ref), None)
    if found is None:
        raise _not_found(ref, records)
    return found


def resolve_bag(catalog: Catalog, ref: str) -> BagRecord:
    """A bag by id, name, or unique prefix of either; unknown refs list close matches. An exact id or name
    is found without reading every record; only prefixes and unknown refs list the catalog."""
    ref = ref.strip()
    if (record := catalog.get(ref) or catalog.named(ref)) is not None:
        return record
    records = catalog.all()
    exact = [r for r in records if r.name == ref]
    if exact:
        return exact[0]
    matches = [r for r in records if r.id.startswith(ref) or r.name.startswith(ref)] if ref else []
    if len(matches) == 1:
        return matches[0]
    if len(matches) > 1:
        names = ", ".join(f"{r.name} ({r.id})" for r in matches[:10])
        raise AmbiguousBagError(f"{ref!r} matches several bags: {names}; give more of the name or id")
    raise _not_found(ref, records)


def ready_record(catalog: Catalog, ref: str) -> BagRecord:
    """A bag that finished ingest; a bag still ingesting or failed is an error saying which."""
    record = resolve_bag(catalog, ref)
    if record.status == "ingesting":
        done = f" ({record.progress:.0%} done)" if record.progress is not None else ""
        raise BagNotReadyError(f"bag {record.name} is still being ingested{done}; try again in a few seconds")
    if record.status == "failed":
        raise BagNotReadyError(f"bag {record.name} could not be ingested: {record.error}")
    return record
