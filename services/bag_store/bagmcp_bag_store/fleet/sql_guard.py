"""What SQL a caller may send: one SELECT (or WITH ... SELECT) over the views the caller may read, and no
table function but a few generators. Checked on DuckDB's own parse (its statement types and the syntax tree
``json_serialize_sql`` gives), before anything runs; DuckDB's external access is off besides (engine.py), so
a file, URL or extension that slipped past this check would still be refused by DuckDB itself.
"""

from __future__ import annotations

import json
from collections.abc import Collection, Iterator
from dataclasses import dataclass

import duckdb

from bagmcp_bag_store.errors import QueryError, QueryForbiddenError
from bagmcp_bag_store.fleet.views import VIEWS, describe

MAX_SQL_CHARS = 20_000
GENERATORS = frozenset({"range", "generate_series", "unnest"})
_OWN_SCHEMAS = frozenset({"", "main", "memory", "temp"})


@dataclass(frozen=True)
class CheckedQuery:
    """The one statement's text and the views it reads."""

    text: str
    views: frozenset[str]


def _nodes(tree: object) -> Iterator[dict[str, object]]:
    if isinstance(tree, dict):
        yield tree
        for value in tree.values():
            yield from _nodes(value)
    elif isinstance(tree, list):
        for value in tree:
            yield from _nodes(value)


def _cte_names(tree: object) -> set[str]:
    names: set[str] = set()
    for node in _nodes(tree):
        entries = node.get("map")
        for entry in entries if isinstance(entries, list) else []:
            if isinstance(entry, dict) and isinstance(key := entry.get("key"), str) and "value" in entry:
                names.add(key.lower())
    return names


def _one_select(con: duckdb.DuckDBPyConnection, sql: str) -> str:
    if not sql.strip():
        raise QueryError(
            "sql is empty; send one SELECT over the views, e.g. SELECT bag, max(speed) FROM poses GROUP BY bag"
        )
    if len(sql) > MAX_SQL_CHARS:
        raise QueryError(f"sql is {len(sql)} characters, more than {MAX_SQL_CHARS}; send a shorter query")
    try:
        statements = con.extract_statements(sql)
    except duckdb.Error as err:
        raise QueryError(f"the SQL does not parse: {_first_line(err)}") from err
    if len(statements) != 1:
        raise QueryError(f"send exactly one SELECT statement, not {len(statements)}")
    kind = statements[0].type
    if kind != duckdb.StatementType.SELECT:
        name = str(kind).rsplit(".", 1)[-1]
        raise QueryError(f"only SELECT (or WITH ... SELECT) is allowed, not {name}; the views are read-only")
    return str(statements[0].query)


def _tree(con: duckdb.DuckDBPyConnection, text: str) -> object:
    rows = con.execute("SELECT json_serialize_sql(?::VARCHAR)", [text]).fetchall()
    tree = json.loads(rows[0][0]) if rows else {}
    if not isinstance(tree, dict) or tree.get("error"):
        message = tree.get("error_message") if isinstance(tree, dict) else None
        raise QueryError(f"the SQL cannot be checked ({message}); send one plain SELECT over the views")
    return tree


@dataclass(frozen=True)
class Parsed:
    """What a statement reads: its text, table references (name, schema, catalog), table functions and CTEs."""

    text: str
    tables: tuple[tuple[str, str, str], ...]
    functions: tuple[str, ...]
    ctes: frozenset[str]


def parse_query(con: duckdb.DuckDBPyConnection, sql: str) -> Parsed:
    """``sql`` parsed, if it is one SELECT (about 10 ms: callers keep the result by text)."""
    text = _one_select(con, sql)
    tree = _tree(con, text)
    tables: list[tuple[str, str, str]] = []
    functions: list[str] = []
    for node in _nodes(tree):
        if node.get("type") == "TABLE_FUNCTION":
            function = node.get("function")
            functions.append(str(function.get("function_name", "?")) if isinstance(function, dict) else "?")
        if node.get("type") == "BASE_TABLE":
            names = (node.get("table_name", ""), node.get("schema_name", ""), node.get("catalog_name", ""))
            tables.append((str(names[0]), str(names[1]), str(names[2])))
    return Parsed(text, tuple(tables), tuple(functions), frozenset(_cte_names(tree)))


def check_query(parsed: Parsed, *, readable: Collection[str]) -> CheckedQuery:
    """The query if it reads only views in ``readable`` (and its own CTEs) and no table function but the
    generators; else a QueryError that names what it may read."""
    for name in parsed.functions:
        if name.lower() not in GENERATORS:
            raise QueryError(
                f"table function {name}() is not allowed (no files, URLs or catalogs); read the views: "
                f"{', '.join(readable)}"
            )
    views = {_view_of(table, parsed.ctes, readable) for table in parsed.tables}
    views.discard("")
    return CheckedQuery(parsed.text, frozenset(views))


def _view_of(table: tuple[str, str, str], ctes: frozenset[str], readable: Collection[str]) -> str:
    """The view a table reference reads ("" for one of the query's own CTEs); refuses anything else."""
    name, schema, catalog = table
    if schema.lower() not in _OWN_SCHEMAS or catalog.lower() not in _OWN_SCHEMAS:
        raise QueryError(f"{catalog}.{schema}.{name} is not a view here; the views are: {', '.join(readable)}")
    lowered = name.lower()
    if lowered in ctes and not schema:
        return ""
    if lowered not in VIEWS:
        raise QueryError(f"there is no table {name!r}; the views are:\n{describe(list(readable))}")
    if lowered not in readable:
        raise QueryForbiddenError(
            f"this token may not read the {lowered} view (it may call none of {', '.join(VIEWS[lowered].tools)}); "
            f"it may read: {', '.join(readable) or 'no view'}"
        )
    return lowered


def _first_line(err: Exception) -> str:
    return " ".join(str(err).split("\n")[0:1]).strip()
