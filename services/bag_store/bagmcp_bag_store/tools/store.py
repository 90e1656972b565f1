"""What the bag-store's declared tools work on (tools/search_tools.py, tools/fleet_tools.py)."""

from __future__ import annotations

from dataclasses import dataclass

from bagmcp_bag_store.fleet.service import Fleet
from bagmcp_bag_store.ingest.ingest import Ingestor
from bagmcp_bag_store.ingest.shelf import Shelf
from bagmcp_shared.access import BagAccess


@dataclass(frozen=True)
class Store:
    """The bags, where new bags go, the questions across bags, and the answer budget."""

    access: BagAccess
    shelf: Shelf
    ingestor: Ingestor
    fleet: Fleet
    budget_bytes: int
