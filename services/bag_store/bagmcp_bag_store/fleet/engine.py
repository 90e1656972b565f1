"""Running a checked query in DuckDB over the views of every ready bag, within limits.

One in-memory database per process, opened with external access off (no files, URLs, ATTACH, COPY or
extension loading), no extension auto-install, a memory limit and a thread count, then its configuration
locked so SQL cannot change any of it. Each query gets its own cursor (its own registered views: the Arrow
tables of tables.py, read in place), a timer that interrupts it at the time limit, and its answer kept in a
temporary table so the total is known while only ``max_rows`` rows leave DuckDB. DuckDB releases the GIL
while it runs, so a query at its limit leaves the server answering other calls.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import duckdb
import pyarrow as pa

from bagmcp_bag_store.errors import QueryError, QueryStoppedError
from bagmcp_bag_store.fleet.extract import bags_of
from bagmcp_bag_store.fleet.sql_guard import CheckedQuery, check_query
from bagmcp_bag_store.fleet.tables import BagName, FleetTables
from bagmcp_bag_store.fleet.views import VIEWS, describe
from bagmcp_bag_store.settings import QueryLimits
from bagmcp_shared.catalog import BagRecord, Catalog

Progress = Callable[[float, str], None]
_ANSWER = "fleet_answer"


@dataclass
class Outcome:
    table: pa.Table
    total_rows: int
    bags: int
    missing: list[str] = field(default_factory=list)
    elapsed_ms: float = 0.0


def _connect(limits: QueryLimits) -> duckdb.DuckDBPyConnection:
    config = {
        "enable_external_access": False,
        "autoinstall_known_extensions": False,
        "autoload_known_extensions": False,
        "allow_community_extensions": False,
        "memory_limit": f"{limits.memory_mb}MB",
        "threads": limits.threads,
        "lock_configuration": True,
    }
    return duckdb.connect(":memory:", config=config)  # type: ignore[arg-type]


class FleetEngine:
    def __init__(self, catalog: Catalog, tables: FleetTables, limits: QueryLimits) -> None:
        self._catalog = catalog
        self.tables = tables
        self.limits = limits
        self._db: duckdb.DuckDBPyConnection | None = None
        self._open = threading.Lock()

    def _cursor(self) -> duckdb.DuckDBPyConnection:
        with self._open:
            if self._db is None:
                self._db = _connect(self.limits)
            return self._db.cursor()

    def ready_bags(self) -> list[BagRecord]:
        return [r for r in self._catalog.all() if r.status == "ready" and r.summary is not None]

    def check(self, sql: str, *, readable: Sequence[str]) -> CheckedQuery:
        cursor = self._cursor()
        try:
            return check_query(cursor, sql, readable=readable)
        finally:
            cursor.close()

    def warm(self, sql: str, *, readable: Sequence[str]) -> bool:
        """Whether the query's views are all in memory (it then runs inline, without a job)."""
        checked = self.check(sql, readable=readable)
        names = [BagName(r.id, r.name) for r in self.ready_bags()]
        return all(self.tables.warm(v, names) for v in checked.views if v != "bags")

    def run(
        self,
        sql: str,
        *,
        readable: Sequence[str],
        max_rows: int,
        params: Sequence[object] = (),
        progress: Progress | None = None,
    ) -> Outcome:
        """``sql`` over the views in ``readable``; ``params`` fill its ``?`` placeholders (find_bags' values)."""
        began = time.perf_counter()
        cursor = self._cursor()
        try:
            checked = check_query(cursor, sql, readable=readable)
            records = self.ready_bags()
            missing = self._register(cursor, checked, records, progress)
            table, total = self._execute(cursor, checked, max_rows=max_rows, params=params)
        finally:
            cursor.close()
        return Outcome(table, total, len(records), missing, round((time.perf_counter() - began) * 1000, 3))

    def _register(
        self,
        cursor: duckdb.DuckDBPyConnection,
        checked: CheckedQuery,
        records: list[BagRecord],
        progress: Progress | None,
    ) -> list[str]:
        names = [BagName(r.id, r.name) for r in records]
        missing: set[str] = set()
        for view in sorted(checked.views):
            if view == "bags":
                table = bags_of([(r, r.summary) for r in records if r.summary is not None])
            else:
                joined = self.tables.view(view, names, progress)
                table, missing = joined.table, missing | set(joined.missing)
            cursor.register(view, table)
        return sorted(missing)

    def _execute(
        self, cursor: duckdb.DuckDBPyConnection, checked: CheckedQuery, *, max_rows: int, params: Sequence[object]
    ) -> tuple[pa.Table, int]:
        timer = threading.Timer(self.limits.timeout_s, cursor.interrupt)
        timer.start()
        try:
            cursor.execute(f"CREATE TEMP TABLE {_ANSWER} AS\n{checked.text}\n", list(params) or None)
            counted = cursor.execute(f"SELECT count(*) FROM {_ANSWER}").fetchall()[0]
            table = cursor.sql(f"SELECT * FROM {_ANSWER} LIMIT {int(max_rows)}").to_arrow_table()
        except duckdb.InterruptException as err:
            raise QueryStoppedError(
                f"the query ran past the time limit of {self.limits.timeout_s:g} s and was stopped; filter earlier "
                "(WHERE on bag, topic or offset_s), aggregate, or avoid joining every row with every row"
            ) from err
        except duckdb.OutOfMemoryException as err:
            raise QueryStoppedError(
                f"the query needed more than the memory limit of {self.limits.memory_mb} MB and was stopped; "
                "aggregate or filter before joining"
            ) from err
        except duckdb.Error as err:
            raise QueryError(_explained(err, checked)) from err
        finally:
            timer.cancel()
        return table, int(counted[0]) if counted else 0


def _explained(err: duckdb.Error, checked: CheckedQuery) -> str:
    """DuckDB's message (first line), with the columns of the views the query reads when it names a wrong one."""
    first = str(err).split("\n")[0].strip()
    if isinstance(err, duckdb.BinderException | duckdb.CatalogException):
        views = sorted(checked.views) or list(VIEWS)
        return f"{first}; the views it reads have these columns:\n{describe(views)}"
    return f"{first}; fix the SQL and try again"
