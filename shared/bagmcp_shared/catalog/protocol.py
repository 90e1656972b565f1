"""The catalog seam: bag records by id with unique names, in memory (embedded) or in Redis (team)."""

from __future__ import annotations

from typing import Protocol

from bagmcp_shared.catalog.models import BagRecord


class Catalog(Protocol):
    """Records by id. Writes are conditional so concurrent uploads, ingests and deletes never
    resurrect a deleted bag or list one content twice."""

    def get(self, bag_id: str) -> BagRecord | None: ...
    def named(self, name: str) -> BagRecord | None:
        """The bag holding ``name`` (from the name reservations, without reading every record)."""
        ...

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
