"""Running a checked query in DuckDB over the views of every ready bag, within limits.

One in-memory database per process, opened with external access off (no files, URLs, ATTACH, COPY or
extension loading), no extension auto-install, a memory limit and a thread count, then its configuration
locked so SQL cannot change any of it. Each query gets its own cursor (its own registered views: the Arrow
tables of tables.py, read in place) and a timer that interrupts it at the time limit; its answer streams
out in batches, the first ``max_rows`` rows kept and the rest only counted, so the total is known without
holding every row. DuckDB releases the GIL
while it runs, so a query at its limit leaves the server answering other calls.
"""

from __future__ import annotations

import threading
import time
from collections import OrderedDict
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field

import duckdb
import pyarrow as pa

from bagmcp_bag_store.errors import QueryError, QueryStoppedError
from bagmcp_bag_store.fleet.extract import bags_of
from bagmcp_bag_store.fleet.listing import ReadyBags
from bagmcp_bag_store.fleet.sql_guard import CheckedQuery, Parsed, check_query, parse_query
from bagmcp_bag_store.fleet.tables import FleetTables
from bagmcp_bag_store.fleet.views import VIEWS, describe
from bagmcp_bag_store.settings import QueryLimits
from bagmcp_shared.catalog import BagRecord, Catalog

Progress = Callable[[float, str], None]
BATCH_ROWS = 8192
PARSED_KEPT = 256


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
        self.ready_bags = ReadyBags(catalog)
        self.tables = tables
        self.limits = limits
        self._db: duckdb.DuckDBPyConnection | None = None
        self._open = threading.Lock()
        self._parsed: OrderedDict[str, Parsed] = OrderedDict()  # by SQL text: a warm query is not parsed again

    def _cursor(self) -> duckdb.DuckDBPyConnection:
        with self._open:
            if self._db is None:
                self._db = _connect(self.limits)
            return self._db.cursor()

    def forget(self, bag_id: str) -> None:
        """Drop a bag deleted through this process from the listing and the rows in memory."""
        self.ready_bags.forget()
        self.tables.forget(bag_id)

    def check(self, sql: str, *, readable: Sequence[str]) -> CheckedQuery:
        with self._open:
            parsed = self._parsed.get(sql)
        if parsed is None:
            cursor = self._cursor()
            try:
                parsed = parse_query(cursor, sql)
            finally:
                cursor.close()
            with self._open:
                self._parsed[sql] = parsed
                while len(self._parsed) > PARSED_KEPT:
                    self._parsed.popitem(last=False)
        return check_query(parsed, readable=readable)

    def warm(self, sql: str, *, readable: Sequence[str]) -> bool:
        """Whether the query's views are all in memory (it then runs inline, without a job); the cold ones
        start being read here in the background, for the next query."""
        checked = self.check(sql, readable=readable)
        return self.warm_views(checked.views)

    def warm_views(self, views: Iterable[str]) -> bool:
        bags = self.ready_bags()
        cold = [v for v in views if v != "bags" and not self.tables.warm(v, bags)]
        for view in cold:
            self.tables.prefetch(view, bags)
        return not cold

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
        checked = self.check(sql, readable=readable)
        cursor = self._cursor()
        try:
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
        missing: set[str] = set()
        for view in sorted(checked.views):
            if view == "bags":
                table = bags_of([(r, r.summary) for r in records if r.summary is not None])
            else:
                joined = self.tables.view(view, records, progress)
                table, missing = joined.table, missing | set(joined.missing)
            cursor.register(view, table)
        return sorted(missing)

    def _execute(
        self, cursor: duckdb.DuckDBPyConnection, checked: CheckedQuery, *, max_rows: int, params: Sequence[object]
    ) -> tuple[pa.Table, int]:
        timer = threading.Timer(self.limits.timeout_s, cursor.interrupt)
        timer.start()
        try:
            return _first_rows(
                cursor.sql(checked.text, params=list(params) or None).to_arrow_reader(BATCH_ROWS), max_rows
            )
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


def _first_rows(reader: pa.RecordBatchReader, max_rows: int) -> tuple[pa.Table, int]:
    """The first ``max_rows`` rows, and how many the query produced (the rest are counted, not kept)."""
    kept: list[pa.RecordBatch] = []
    total = 0
    for batch in reader:
        if total < max_rows:
            kept.append(batch.slice(0, max_rows - total))
        total += batch.num_rows
    return pa.Table.from_batches(kept, schema=reader.schema), total


def _explained(err: duckdb.Error, checked: CheckedQuery) -> str:
    """DuckDB's message (first line), with the columns of the views the query reads when it names a wrong one."""
    first = str(err).split("\n")[0].strip()
    if isinstance(err, duckdb.BinderException | duckdb.CatalogException):
        views = sorted(checked.views) or list(VIEWS)
        return f"{first}; the views it reads have these columns:\n{describe(views)}"
    return f"{first}; fix the SQL and try again"
