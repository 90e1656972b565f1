"""What the bag-store's declared tools work on: the long-work tools a ``Store`` (tools/search_tools.py,
tools/fleet_tools.py), the reading tools a ``Reading`` (tools/catalog_tools.py, tools/message_tools.py)."""

from __future__ import annotations

from dataclasses import dataclass

from bagmcp_bag_store.fleet.service import Fleet
from bagmcp_bag_store.ingest.ingest import Ingestor
from bagmcp_bag_store.ingest.shelf import Shelf
from bagmcp_bag_store.queries.page_cursor import CursorSigner
from bagmcp_shared.access import BagAccess


@dataclass(frozen=True)
class Store:
    """The bags, where new bags go, the questions across bags, and the answer budget."""

    access: BagAccess
    shelf: Shelf
    ingestor: Ingestor
    fleet: Fleet
    budget_bytes: int


@dataclass(frozen=True)
class Reading:
    """The bags, the answer budget and the signer of page cursors (its key is the MCP server's: from the
    service credential, or random per process), so the reading tools are served apart from the jobs."""

    access: BagAccess
    budget_bytes: int
    cursors: CursorSigner
