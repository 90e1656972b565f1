"""Fixtures for every test: real servers, generated bags and the shared recordings corpus."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from tests.fixtures.bagfactory import BAG_KINDS, BagKind, write_bag
from tests.fixtures.drive_bags import write_drive_bags

pytest_plugins = ["tests.fixtures.servers"]

CORPUS = Path(os.environ.get("BAGMCP_CORPUS", Path(__file__).resolve().parents[2] / "shared/data/bags"))


@pytest.fixture(scope="session")
def corpus() -> Path:
    """The real recordings beside the checkout; tests using it skip when it is absent."""
    if not CORPUS.is_dir():
        pytest.skip(f"recorded bag corpus not found at {CORPUS} (set BAGMCP_CORPUS)")
    return CORPUS


@pytest.fixture(scope="session")
def scenario_bags(tmp_path_factory: pytest.TempPathFactory) -> dict[BagKind, Path]:
    """One generated scenario bag of each kind (ROS 1, ROS 2 sqlite3, ROS 2 MCAP)."""
    directory = tmp_path_factory.mktemp("scenario-bags")
    return {kind: write_bag(kind, directory) for kind in BAG_KINDS}


@pytest.fixture(params=BAG_KINDS)
def scenario_bag(request: pytest.FixtureRequest, scenario_bags: dict[BagKind, Path]) -> Path:
    kind: BagKind = request.param
    return scenario_bags[kind]


@pytest.fixture(scope="session")
def anyio_backend() -> str:
    return "asyncio"


@pytest.fixture(scope="session")
def drive_bags(tmp_path_factory: pytest.TempPathFactory) -> dict[BagKind, Path]:
    """The drive scenario (known geometry, logs, TF, images) in the three formats, written once per session
    (per test process) for every test that reads it."""
    return write_drive_bags(tmp_path_factory.mktemp("drive-bags"))
