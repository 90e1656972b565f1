"""Fixtures for unit tests: every service composed in this process over the scenario bags."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest

from tests.fixtures.bagfactory import BagKind
from tests.fixtures.compressed_bags import COMPRESSED_KINDS, CompressedKind, write_compressed
from tests.fixtures.inprocess import InProcess, copy_bags, in_process
from tests.fixtures.once_per_run import written_once
from tests.fixtures.small_bags import (
    write_instant_bag,
    write_late_camera_bag,
    write_late_topic_bag,
    write_old_tf_drive,
)

SCENARIO_NAMES = ["scenario", "scenario_db3", "scenario_mcap"]
DRIVE_NAMES = ["drive", "drive_db3", "drive_mcap"]


@pytest.fixture(scope="session")
def served(scenario_bags: dict[BagKind, Path], tmp_path_factory: pytest.TempPathFactory) -> Iterator[InProcess]:
    folder = copy_bags(list(scenario_bags.values()), tmp_path_factory.mktemp("served") / "bags")
    with in_process(folder, tmp_path_factory.mktemp("data")) as services:
        yield services


@pytest.fixture(scope="session")
def served_drive(drive_bags: dict[BagKind, Path], tmp_path_factory: pytest.TempPathFactory) -> Iterator[InProcess]:
    folder = copy_bags(list(drive_bags.values()), tmp_path_factory.mktemp("served-drive") / "bags")
    with in_process(folder, tmp_path_factory.mktemp("data")) as services:
        yield services


@pytest.fixture(scope="session")
def served_small(tmp_path_factory: pytest.TempPathFactory) -> Iterator[InProcess]:
    """The small bags of tests/fixtures/small_bags.py (old_tf, late_imu, late_camera, instant)."""
    written = written_once(tmp_path_factory, "small-bags", _write_small_bags)
    folder = copy_bags(list(written.values()), tmp_path_factory.mktemp("served-small") / "bags")
    with in_process(folder, tmp_path_factory.mktemp("data")) as services:
        yield services


@pytest.fixture(scope="session")
def compressed_bags(tmp_path_factory: pytest.TempPathFactory) -> dict[CompressedKind, Path]:
    """The scenario bag in every compression of tests/fixtures/compressed_bags.py, written once per run (0.5 s of
    CPU; four test files wrote them, some per test). Read-only: a test that damages one damages a copy."""
    paths = written_once(tmp_path_factory, "compressed-bags", _write_compressed_bags)
    return {kind: paths[kind] for kind in COMPRESSED_KINDS}


def _write_compressed_bags(folder: Path) -> dict[CompressedKind, Path]:
    return {kind: write_compressed(kind, folder) for kind in COMPRESSED_KINDS}


def _write_small_bags(folder: Path) -> dict[str, Path]:
    writers = (write_old_tf_drive, write_late_topic_bag, write_late_camera_bag, write_instant_bag)
    return {write.__name__: write(folder) for write in writers}
