"""Long analyses that decode a bag say how far along they are, in step with the messages read, and never
go backwards (the progress of a job is what get_job and the MCP progress notifications show)."""

from __future__ import annotations

from collections.abc import Iterator

import pytest

from bagmcp_analysis.queries.lidar import LidarParams, analyze_lidar
from bagmcp_analysis.queries.logs import LogParams, analyze_logs
from bagmcp_analysis.queries.statistics import StatisticsParams, topic_statistics
from bagmcp_analysis.queries.tf import TfTreeParams, get_tf_tree
from bagmcp_analysis.queries.trajectory import TrajectoryParams, analyze_trajectory
from bagmcp_analysis.queries.window import WindowParams, summarize_window
from bagmcp_shared.access import BagAccess
from tests.fixtures.inprocess import InProcess
from tests.unit.analysis.decoding import decoding


class Recorded:
    """Progress that remembers every report."""

    def __init__(self) -> None:
        self.fractions: list[float] = []
        self.messages: list[str] = []

    def __call__(self, fraction: float, message: str) -> None:
        self.fractions.append(fraction)
        self.messages.append(message)

    def cancelled(self) -> bool:
        return False


@pytest.fixture
def decoded(served_drive: InProcess) -> Iterator[BagAccess]:
    with decoding(served_drive.composition.embedded.resources.access) as access:
        yield access


def test_decoding_the_tf_topics_reports_the_share_of_transforms_read(decoded: BagAccess) -> None:
    progress = Recorded()
    get_tf_tree(decoded, TfTreeParams(bag="drive_mcap"), progress)
    # /tf (1201 messages) is the first half, /tf_static (1) the second; a report every 1000 messages read
    assert progress.fractions == pytest.approx([0.0, 0.5 * 1000 / 1201, 0.5])
    assert progress.messages[1] == "read 1000 of 1201 messages of /tf"


def test_decoding_the_logs_reports_each_log_topic_in_turn(decoded: BagAccess) -> None:
    progress = Recorded()
    analyze_logs(decoded, LogParams(bag="drive"), progress)
    assert progress.fractions == [0.0, 0.5]  # /rosout, then /rosout_agg
    assert [m.rsplit(" ", 1)[-1] for m in progress.messages] == ["/rosout", "/rosout_agg"]


def test_a_trajectory_and_a_lidar_window_report_while_decoding(decoded: BagAccess) -> None:
    path = Recorded()
    analyze_trajectory(decoded, TrajectoryParams(bag="drive_db3"), path)
    assert path.fractions == pytest.approx([0.0, 1000 / 1201])
    scans = Recorded()
    analyze_lidar(decoded, LidarParams(bag="drive_db3", within_m=0.5), scans)
    assert scans.fractions == [0.0]  # 601 scans: one report before the first


def test_reading_the_stamps_of_a_topic_reports_how_many_there_are(decoded: BagAccess) -> None:
    progress = Recorded()
    topic_statistics(decoded, StatisticsParams(bag="drive_mcap", topic="/imu"), progress)
    assert progress.messages == ["read 0 of 2902 messages of /imu"]  # then one report every 10,000


def test_a_window_summary_moves_forward_through_its_four_steps(decoded: BagAccess) -> None:
    progress = Recorded()
    summarize_window(decoded, WindowParams(bag="drive", start=19, end=23), progress)
    assert progress.fractions == sorted(progress.fractions)
    assert progress.fractions[0] == 0.0
    assert max(progress.fractions) >= 0.75  # the last step (the lidar window) reported
    assert any(m.startswith("timing /imu") for m in progress.messages)
