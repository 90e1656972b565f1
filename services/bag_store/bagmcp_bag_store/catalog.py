"""The catalog: bag records by id, with unique names; and resolving what a caller calls a bag."""

from __future__ import annotations

import difflib
from typing import Protocol

from bagmcp_bag_store.errors import AmbiguousBagError, BagNotFoundError
from bagmcp_bag_store.models import BagRecord


class Catalog(Protocol):
    """Records by id. Writes are conditional so concurrent uploads, ingests and deletes never
    resurrect a deleted bag or list one content twice."""

    def get(self, bag_id: str) -> BagRecord | None: ...
    def all(self) -> list[BagRecord]: ...
    def add(self, record: BagRecord) -> bool:
        """Store a new record; False (and nothing written) when the id is already listed."""
        ...

    def replace(self, record: BagRecord) -> bool:
        """Update a listed record; False (and nothing written) when it was deleted meanwhile."""
        ...

    def claim_name(self, name: str, bag_id: str) -> None:
        """Reserve ``name`` for ``bag_id``; NameTakenError when another bag holds it."""
        ...

    def release_name(self, name: str, bag_id: str) -> None: ...
    def delete(self, bag_id: str) -> None: ...


def resolve_bag(catalog: Catalog, ref: str) -> BagRecord:
    """A bag by id, name, or unique prefix of either; unknown refs list close matches."""
    ref = ref.strip()
    if (record := catalog.get(ref)) is not None:
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
    close = difflib.get_close_matches(ref, [r.name for r in records], n=5, cutoff=0.4)
    hint = f"; did you mean: {', '.join(close)}?" if close else ""
    known = "" if close else f"; {len(records)} bags exist (call list_bags)"
    raise BagNotFoundError(f"no bag called {ref!r}{hint}{known}")
