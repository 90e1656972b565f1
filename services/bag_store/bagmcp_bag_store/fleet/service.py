"""The fleet's queries as the bag-store runs them: query_bags and find_bags over one engine, inline when
their views are in memory, else as jobs (the first query of a process reads every bag's files)."""

from __future__ import annotations

from dataclasses import dataclass

from bagmcp_bag_store.fleet.answers import QueryAnswer, shaped
from bagmcp_bag_store.fleet.engine import FleetEngine, Progress
from bagmcp_bag_store.fleet.files import FleetFiles
from bagmcp_bag_store.fleet.find import FindAnswer, find_bags
from bagmcp_bag_store.fleet.find_params import FindParams, QueryParams
from bagmcp_bag_store.fleet.tables import FleetTables
from bagmcp_bag_store.settings import QueryLimits
from bagmcp_shared.access import BagFiles
from bagmcp_shared.catalog import Catalog
from bagmcp_shared.storage import ObjectStore

FIND_VIEWS = ("topics", "poses", "scans", "logs")


@dataclass(frozen=True)
class Fleet:
    engine: FleetEngine
    budget_bytes: int

    def query(self, params: QueryParams, progress: Progress | None = None) -> QueryAnswer:
        outcome = self.engine.run(params.sql, readable=params.readable, max_rows=params.max_rows, progress=progress)
        return shaped(outcome, budget_bytes=self.budget_bytes)

    def find(self, params: FindParams, progress: Progress | None = None) -> FindAnswer:
        return find_bags(self.engine, params, params.readable, progress)

    def query_is_small(self, params: QueryParams) -> bool:
        return self.engine.warm(params.sql, readable=params.readable)

    def find_is_small(self, _params: FindParams) -> bool:
        return self.engine.warm_views(FIND_VIEWS)


def build_fleet(
    catalog: Catalog, store: ObjectStore, files: BagFiles, *, limits: QueryLimits, budget_bytes: int
) -> Fleet:
    tables = FleetTables(FleetFiles(store, files), max_bytes=limits.cache_bytes)
    return Fleet(FleetEngine(catalog, tables, limits), budget_bytes=budget_bytes)
