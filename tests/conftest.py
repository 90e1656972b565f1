"""Fixtures for every test: real servers, generated bags and the shared recordings corpus."""

from __future__ import annotations

import os
from collections.abc import Iterator
from pathlib import Path

import pytest

from tests.fixtures.bagfactory import BAG_KINDS, BagKind, write_bag
from tests.fixtures.drive_bags import write_drive_bags
from tests.fixtures.once_per_run import written_once

pytest_plugins = ["tests.fixtures.servers"]

INTEGRATION = Path(__file__).resolve().parent / "integration"
CORPUS = Path(os.environ.get("BAGMCP_CORPUS", Path(__file__).resolve().parents[2] / "shared/data/bags"))


def pytest_ignore_collect(collection_path: Path, config: pytest.Config) -> bool | None:
    """Under ``-m 'not integration'`` (make unit) skip tests/integration whole: tests/integration/conftest.py
    marks every test there ``integration``, so all would be deselected, but only after each test process had
    imported them (about 2 s of CPU per process without cached bytecode, measured with --collect-only)."""
    unit_tier = " ".join(str(config.option.markexpr).split()) == "not integration"
    return True if unit_tier and collection_path == INTEGRATION else None


@pytest.fixture(scope="session")
def corpus() -> Iterator[Path]:
    """The real recordings beside the checkout; tests using it skip when it is absent. Nothing may write
    there (a served folder is never written to): every file, its size and modification time, are the same
    when the session ends (SQLite opened without ``immutable`` once added -wal/-shm files beside .db3 bags)."""
    if not CORPUS.is_dir():
        pytest.skip(f"recorded bag corpus not found at {CORPUS} (set BAGMCP_CORPUS)")
    before = _files_of(CORPUS)
    yield CORPUS
    after = _files_of(CORPUS)
    changed = sorted(name for name in before.keys() | after.keys() if before.get(name) != after.get(name))
    assert not changed, f"tests or the product wrote into the corpus: {changed}"


def _files_of(root: Path) -> dict[str, tuple[int, int]]:
    return {str(p.relative_to(root)): (p.stat().st_size, p.stat().st_mtime_ns) for p in root.rglob("*") if p.is_file()}


@pytest.fixture(scope="session")
def scenario_bags(tmp_path_factory: pytest.TempPathFactory) -> dict[BagKind, Path]:
    """One generated scenario bag of each kind (ROS 1, ROS 2 sqlite3, ROS 2 MCAP), written once per run."""
    paths = written_once(tmp_path_factory, "scenario-bags", lambda folder: {k: write_bag(k, folder) for k in BAG_KINDS})
    return {kind: paths[kind] for kind in BAG_KINDS}


@pytest.fixture(params=BAG_KINDS)
def scenario_bag(request: pytest.FixtureRequest, scenario_bags: dict[BagKind, Path]) -> Path:
    kind: BagKind = request.param
    return scenario_bags[kind]


@pytest.fixture(scope="session")
def anyio_backend() -> str:
    return "asyncio"


@pytest.fixture(scope="session")
def drive_bags(tmp_path_factory: pytest.TempPathFactory) -> dict[BagKind, Path]:
    """The drive scenario (known geometry, logs, TF, images) in the three formats, written once per run (the
    first test process to ask writes, the other reads) for every test that reads it."""
    paths = written_once(tmp_path_factory, "drive-bags", write_drive_bags)
    return {kind: paths[kind] for kind in BAG_KINDS}
