"""Every analysis answers the same from the columnar index as from decoding the bag."""

from __future__ import annotations

from typing import Any

import pytest
from pydantic import BaseModel

from bagmcp_analysis.queries.lidar import LidarParams, analyze_lidar
from bagmcp_analysis.queries.logs import LogParams, analyze_logs
from bagmcp_analysis.queries.statistics import StatisticsParams, topic_statistics
from bagmcp_analysis.queries.tf import TfTreeParams, TransformParams, get_tf_tree, lookup_transform
from bagmcp_analysis.queries.trajectory import TrajectoryParams, analyze_trajectory
from bagmcp_analysis.queries.window import WindowParams, summarize_window
from bagmcp_shared.jobs import Unreported
from tests.fixtures.inprocess import InProcess
from tests.unit.analysis.decoding import decoding
from tests.unit.conftest import DRIVE_NAMES


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
    (lookup_transform, lambda bag: TransformParams(bag=bag, target_frame="map", source_frame="laser", time=13.55)),
    (lookup_transform, lambda bag: TransformParams(bag=bag, target_frame="camera_link", source_frame="odom")),
    (topic_statistics, lambda bag: StatisticsParams(bag=bag, topic="/imu")),
    (summarize_window, lambda bag: WindowParams(bag=bag, start=19, end=27)),
]


@pytest.mark.parametrize("bag", DRIVE_NAMES)
@pytest.mark.parametrize(("question", "params"), QUESTIONS)
def test_the_index_and_decoding_give_the_same_answer(
    served_drive: InProcess, bag: str, question: Any, params: Any
) -> None:
    access = served_drive.composition.embedded.resources.access
    with access.open(bag) as ob:
        assert ob.index is not None
    indexed = question(access, params(bag), Unreported())
    with decoding(access) as without_index:
        decoded = question(without_index, params(bag), Unreported())
    assert _plain(indexed) == _plain(decoded)
    if hasattr(indexed, "source"):
        assert (indexed.source, decoded.source) == ("index", "bag")
