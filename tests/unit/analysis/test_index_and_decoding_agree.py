"""Every analysis answers the same from the columnar index as from decoding the bag."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest
from pydantic import BaseModel

from bagmcp_analysis.job_kinds import (
    LidarParams,
    LogParams,
    StatisticsParams,
    TfTreeParams,
    TrajectoryParams,
    WindowParams,
)
from bagmcp_analysis.queries.lidar import analyze_lidar
from bagmcp_analysis.queries.logs import analyze_logs
from bagmcp_analysis.queries.statistics import topic_statistics
from bagmcp_analysis.queries.tf import get_tf_tree
from bagmcp_analysis.queries.trajectory import analyze_trajectory
from bagmcp_analysis.queries.window import summarize_window
from bagmcp_shared.access import BagAccess, BagFiles
from bagmcp_shared.catalog import BagRecord
from bagmcp_shared.jobs import Unreported
from tests.fixtures.inprocess import InProcess
from tests.unit.conftest import DRIVE_NAMES


class WithoutIndex:
    """The same bag files, but no columnar index: every question is answered by decoding."""

    def __init__(self, files: BagFiles) -> None:
        self._files = files

    def path_for(self, record: BagRecord) -> Path:
        return self._files.path_for(record)

    def index_dir(self, record: BagRecord) -> Path | None:
        return None


def _plain(report: BaseModel) -> Any:
    data = report.model_dump(mode="json")
    data.pop("source", None)
    return data


QUESTIONS = [
    (analyze_trajectory, lambda bag: TrajectoryParams(bag=bag)),
    (analyze_trajectory, lambda bag: TrajectoryParams(bag=bag, topic="/gps/fix", start=2, end=9)),
    (analyze_lidar, lambda bag: LidarParams(bag=bag, within_m=0.5)),
    (analyze_logs, lambda bag: LogParams(bag=bag, min_level="WARN")),
    (get_tf_tree, lambda bag: TfTreeParams(bag=bag, time=10)),
    (topic_statistics, lambda bag: StatisticsParams(bag=bag, topic="/imu")),
    (summarize_window, lambda bag: WindowParams(bag=bag, start=19, end=27)),
]


@pytest.mark.parametrize("bag", DRIVE_NAMES)
@pytest.mark.parametrize(("question", "params"), QUESTIONS)
def test_the_index_and_decoding_give_the_same_answer(
    served_drive: InProcess, bag: str, question: Any, params: Any
) -> None:
    access = served_drive.composition.embedded.resources.access
    decoding = BagAccess(access.catalog, WithoutIndex(access.files))
    with access.open(bag) as ob:
        assert ob.index is not None
    indexed, decoded = question(access, params(bag), Unreported()), question(decoding, params(bag), Unreported())
    assert _plain(indexed) == _plain(decoded)
    if hasattr(indexed, "source"):
        assert (indexed.source, decoded.source) == ("index", "bag")
