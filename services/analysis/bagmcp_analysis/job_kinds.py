"""The analysis service's background work: one task on its own queue, and a typed job kind per long scan.

Every analysis that may decode much of a bag is a job kind: it runs inline when it is small (the index
has the data, or the topic is short) and as a job followed with get_job otherwise.
"""

from __future__ import annotations

from pydantic import BaseModel, Field

from bagmcp_analysis.reports.lidar import LidarReport
from bagmcp_analysis.reports.logs import LogReport
from bagmcp_analysis.reports.statistics import TopicStatisticsReport
from bagmcp_analysis.reports.tf import TfTreeReport, TransformReport
from bagmcp_analysis.reports.trajectory import TrajectoryReport
from bagmcp_analysis.reports.window import WindowReport
from bagmcp_shared.jobs import JobKind
from bagmcp_shared.tasks import TaskRef

QUEUE = "analysis"
RUN_JOB = TaskRef("bagmcp.analysis.run_job", QUEUE)
Time = float | str


class TrajectoryParams(BaseModel):
    bag: str
    topic: str | None = None
    start: Time | None = None
    end: Time | None = None


class LidarParams(BaseModel):
    bag: str
    topic: str | None = None
    time: Time | None = None
    start: Time | None = None
    end: Time | None = None
    within_m: float | None = Field(default=None, gt=0)


class LogParams(BaseModel):
    bag: str
    topic: str | None = None
    level: str | None = None
    min_level: str | None = None
    node: str | None = None
    contains: str | None = None
    start: Time | None = None
    end: Time | None = None
    summary: bool = True
    limit: int = Field(default=50, ge=1, le=500)
    offset: int = Field(default=0, ge=0)


class TfTreeParams(BaseModel):
    bag: str
    time: Time | None = None


class TransformParams(BaseModel):
    bag: str
    target_frame: str
    source_frame: str
    time: Time | None = None


class StatisticsParams(BaseModel):
    bag: str
    topic: str
    gap_periods: float = Field(default=3.0, gt=1)


class WindowParams(BaseModel):
    bag: str
    start: Time | None = None
    end: Time | None = None


TRAJECTORY = JobKind("analysis.trajectory", TrajectoryParams, TrajectoryReport, RUN_JOB)
LIDAR = JobKind("analysis.lidar", LidarParams, LidarReport, RUN_JOB)
LOGS = JobKind("analysis.logs", LogParams, LogReport, RUN_JOB)
TF_TREE = JobKind("analysis.tf_tree", TfTreeParams, TfTreeReport, RUN_JOB)
TRANSFORM = JobKind("analysis.lookup_transform", TransformParams, TransformReport, RUN_JOB)
STATISTICS = JobKind("analysis.topic_statistics", StatisticsParams, TopicStatisticsReport, RUN_JOB)
WINDOW = JobKind("analysis.summarize_window", WindowParams, WindowReport, RUN_JOB)
