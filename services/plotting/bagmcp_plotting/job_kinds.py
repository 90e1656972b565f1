"""The plotting service's background work: one task on its own queue, and a typed job kind per plot."""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, Field

from bagmcp_plotting.reports import PlotReport
from bagmcp_shared.jobs import JobKind
from bagmcp_shared.tasks import TaskRef

QUEUE = "plotting"
RUN_JOB = TaskRef("bagmcp.plotting.run_job", QUEUE)
Time = float | str


class TimeseriesParams(BaseModel):
    bag: str
    paths: list[str] = Field(min_length=1, max_length=8)
    start: Time | None = None
    end: Time | None = None
    style: Literal["line", "step", "scatter"] = "line"
    title: str | None = None


class XYParams(BaseModel):
    bag: str
    x: str | None = None
    y: str | None = None
    topic: str | None = None
    start: Time | None = None
    end: Time | None = None
    color_by_time: bool = False


class ScanPlotParams(BaseModel):
    bag: str
    topic: str | None = None
    time: Time
    within_m: float | None = Field(default=None, gt=0)


class HistogramParams(BaseModel):
    bag: str
    path: str
    start: Time | None = None
    end: Time | None = None
    bins: int | None = Field(default=None, ge=2, le=500)


class CompareParams(BaseModel):
    bags: list[str] = Field(min_length=1, max_length=6)
    path: str
    align: Literal["start", "motion"] = "start"


PLOT_TIMESERIES = JobKind("plotting.timeseries", TimeseriesParams, PlotReport, RUN_JOB)
PLOT_2D = JobKind("plotting.xy", XYParams, PlotReport, RUN_JOB)
PLOT_SCAN = JobKind("plotting.scan", ScanPlotParams, PlotReport, RUN_JOB)
PLOT_HISTOGRAM = JobKind("plotting.histogram", HistogramParams, PlotReport, RUN_JOB)
COMPARE_RUNS = JobKind("plotting.compare", CompareParams, PlotReport, RUN_JOB)
