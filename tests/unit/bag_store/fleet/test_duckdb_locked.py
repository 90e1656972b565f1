"""The query engine's DuckDB connection itself refuses files, catalogs, extensions and settings: these run
straight on ``_connect``'s connection, past the SQL check, so DuckDB's own configuration (external access off,
configuration locked) is what stops them."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import duckdb
import pyarrow as pa
import pytest

from bagmcp_bag_store.fleet.engine import _connect
from bagmcp_bag_store.settings import QueryLimits

LIMITS = QueryLimits(memory_mb=256, threads=1)
DISABLED = "disabled by configuration"
LOCKED = "the configuration has been locked"


@pytest.fixture
def db() -> Iterator[duckdb.DuckDBPyConnection]:
    connection = _connect(LIMITS)
    yield connection
    connection.close()


def _refused(db: duckdb.DuckDBPyConnection, sql: str) -> str:
    with pytest.raises(duckdb.Error) as refused:
        db.sql(sql).fetchall()
    return str(refused.value)


def test_files_catalogs_extensions_and_copies_are_refused_by_duckdb(
    db: duckdb.DuckDBPyConnection, tmp_path: Path
) -> None:
    other, copied = tmp_path / "other.duckdb", tmp_path / "copied.csv"
    for sql in (
        "SELECT * FROM read_csv('/etc/passwd')",
        "SELECT * FROM glob('/etc/*')",
        "SELECT * FROM read_parquet('s3://bucket/fleet/x.parquet')",
        f"ATTACH '{other}' AS other",
        f"COPY (SELECT 1 AS one) TO '{copied}'",
        "INSTALL httpfs",
    ):
        assert DISABLED in _refused(db, sql), sql
    assert "Loading external extensions is disabled" in _refused(db, "LOAD httpfs")
    assert "does not exist" in _refused(db, "SELECT * FROM '/etc/passwd'")  # no file read in place of a table
    assert not other.exists()
    assert not copied.exists()


def test_settings_are_locked_and_keep_their_values(db: duckdb.DuckDBPyConnection) -> None:
    for sql in (
        "SET enable_external_access = true",
        "SET memory_limit = '64GB'",
        "SET threads = 64",
        "SET lock_configuration = false",
        "RESET enable_external_access",
    ):
        assert LOCKED in _refused(db, sql), sql
    settings = dict(
        db.sql(
            "SELECT name, value FROM duckdb_settings() WHERE name IN "
            "('enable_external_access', 'threads', 'lock_configuration', 'autoinstall_known_extensions')"
        ).fetchall()
    )
    assert settings == {
        "enable_external_access": "false",
        "threads": "1",
        "lock_configuration": "true",
        "autoinstall_known_extensions": "false",
    }


def test_registered_tables_are_still_queried(db: duckdb.DuckDBPyConnection) -> None:
    db.register("poses", pa.table({"bag": ["a", "a", "b"], "speed": [0.5, 1.5, 0.25]}))
    assert db.sql("SELECT bag, max(speed) FROM poses GROUP BY bag ORDER BY bag").fetchall() == [("a", 1.5), ("b", 0.25)]
