"""The plots behind the tools: read the numbers, render a PNG (off the event loop), store it as an
artifact named by the request, and report what was plotted."""

from __future__ import annotations

import struct
from collections.abc import Callable, Sequence
from typing import Annotated, Literal, TypeVar

import numpy as np
from pydantic import BaseModel, ConfigDict, Field

from bagmcp_kit.arguments import BagRef, OptionalTopic, TimeArg
from bagmcp_plotting import drawing
from bagmcp_plotting.artifacts import Artifacts, artifact_id
from bagmcp_plotting.data import PathSeries, read_path, read_paths
from bagmcp_plotting.drawing import Line
from bagmcp_plotting.positions import motion_start, positions
from bagmcp_plotting.reports import Artifact, PlotReport, SeriesOut
from bagmcp_shared.access import BagAccess, OpenBag
from bagmcp_shared.errors import ArgumentError
from bagmcp_shared.jobs import Progress, Unreported, spans
from bagmcp_shared.laser_ranges import laser_ranges
from bagmcp_shared.topics import SCAN, choose_lidar_topic, choose_pose_topic, is_fix
from bagmcp_shared.units import unit_of


def _series_out(series: PathSeries) -> SeriesOut:
    finite = series.values[np.isfinite(series.values)]
    low, high = (float(finite.min()), float(finite.max())) if finite.size else (None, None)
    return SeriesOut(name=series.name, unit=series.unit, points=int(finite.size), min=low, max=high)


def _png_size(png: bytes) -> tuple[int, int]:
    width, height = struct.unpack(">II", png[16:24])
    return int(width), int(height)


# Each plot's name: its job kind is plotting.<name> (tools/plot_tools.py), and so is its artifact ids' kind.
TIMESERIES, XY, SCAN_PLOT, HISTOGRAM, COMPARE = "timeseries", "xy", "scan", "histogram", "compare"
Path = Annotated[str, Field(description="e.g. /odom.twist.twist.linear.x")]


class TimeseriesParams(BaseModel):
    """The arguments of plot_timeseries."""

    bag: BagRef
    paths: Annotated[list[str], Field(min_length=1, max_length=8, description="message paths (1-8)")]
    start: TimeArg | None = None
    end: TimeArg | None = None
    style: Literal["line", "step", "scatter"] = "line"
    title: Annotated[str | None, Field(description="default: the paths and window")] = None


class XYParams(BaseModel):
    """The arguments of plot_2d."""

    bag: BagRef
    x: Annotated[str | None, Field(description="message path")] = None
    y: Annotated[str | None, Field(description="path on x's topic")] = None
    topic: OptionalTopic = None
    start: TimeArg | None = None
    end: TimeArg | None = None
    color_by_time: bool = False


class ScanPlotParams(BaseModel):
    """The arguments of plot_lidar_scan (``within`` is ``within_m`` in the job)."""

    model_config = ConfigDict(validate_by_name=True, validate_by_alias=True)

    bag: BagRef
    time: TimeArg
    topic: OptionalTopic = None
    within_m: Annotated[float | None, Field(gt=0, alias="within", description="m: draw this circle")] = None


class HistogramParams(BaseModel):
    """The arguments of plot_histogram."""

    bag: BagRef
    path: Path
    start: TimeArg | None = None
    end: TimeArg | None = None
    bins: Annotated[int | None, Field(ge=2, le=500, description="default: automatic")] = None


class CompareParams(BaseModel):
    """The arguments of compare_runs."""

    bags: Annotated[list[str], Field(min_length=1, max_length=6, description="bag ids or names (1-6)")]
    path: Path
    align: Literal["start", "motion"] = "start"


def plot_id(access: BagAccess, plot: str, params: BaseModel, bags: list[str]) -> str:
    """The artifact id of a plot: the same request on the same bag contents always gets the same id."""
    return artifact_id(f"plotting.{plot}", params, [access.ready(b).id for b in bags])


def _window_title(ob: OpenBag, lo: int, hi: int) -> str:
    return f"{ob.name}, {(lo - ob.start_ns) / 1e9:.1f}-{(hi - ob.start_ns) / 1e9:.1f} s"


def _window_report(
    ob: OpenBag, lo: int, hi: int, title: str, series: list[SeriesOut], notes: Sequence[str] = ()
) -> PlotReport:
    """The report of a plot of one bag's window, before its PNG is stored (``Plotter._store`` adds it)."""
    start, end = ob.instant(lo), ob.instant(hi)
    return PlotReport(
        bags=[ob.name], title=title, start=start, end=end, series=series, artifact=_PENDING, notes=list(notes)
    )


P = TypeVar("P", bound=BaseModel)
PlotDraw = Callable[[P, Progress, str | None], PlotReport]


class Plotter:
    def __init__(self, access: BagAccess, artifacts: Artifacts) -> None:
        self._access = access
        self._artifacts = artifacts

    def _store(self, key: str, png: bytes, report: PlotReport) -> PlotReport:
        width, height = _png_size(png)
        artifact = Artifact(
            id=key, url=self._artifacts.url(key), mime_type="image/png", bytes=len(png), width=width, height=height
        )
        final = report.model_copy(update={"artifact": artifact})
        self._artifacts.save(key, png, final)
        return final.with_png(png)

    def _plot(
        self, plot: str, params: BaseModel, bags: list[str], make: Callable[[str], PlotReport], key: str | None
    ) -> PlotReport:
        """The stored plot, or ``make`` it; ``key``: the id of a plot the caller already found not stored."""
        if key is not None:
            return make(key)
        found = plot_id(self._access, plot, params, bags)
        return self._artifacts.cached(found, lambda: make(found))

    def now(
        self, draw: PlotDraw[P], plot: str, params: P, bags: list[str], quick: Callable[[P], bool]
    ) -> PlotReport | None:
        """The plot answered while the caller waits, when it is stored or ``quick`` to draw; None for a job.
        Its id (a catalog read per bag and a hash) is computed once, and its stored report looked up once."""
        key = plot_id(self._access, plot, params, bags)
        stored = self._artifacts.find(key)
        if stored is not None:
            return stored
        return draw(params, Unreported(), key) if quick(params) else None

    def timeseries(self, params: TimeseriesParams, progress: Progress, key: str | None = None) -> PlotReport:
        def make(key: str) -> PlotReport:
            with self._access.open(params.bag) as ob:
                lo, hi = ob.window(params.start, params.end)
                series = read_paths(ob, params.paths, lo, hi, progress)
                title = params.title or f"{', '.join(s.name for s in series)} ({_window_title(ob, lo, hi)})"
                lines = [Line(s.name, s.unit, s.t_s(ob.start_ns), s.values) for s in series]
                png = drawing.render_timeseries(lines, style=params.style, title=title)
                return self._store(key, png, _window_report(ob, lo, hi, title, [_series_out(s) for s in series]))

        return self._plot(TIMESERIES, params, [params.bag], make, key)

    def xy(self, params: XYParams, progress: Progress, key: str | None = None) -> PlotReport:
        def make(key: str) -> PlotReport:
            with self._access.open(params.bag) as ob:
                lo, hi = ob.window(params.start, params.end)
                x, y, notes = self.xy_series(ob, params, lo, hi, progress)
                trajectory = params.x is None
                what = f"trajectory of {x.topic}" if trajectory else f"{y.name} against {x.name}"
                title = f"{what} ({_window_title(ob, lo, hi)})"
                png = drawing.render_xy(
                    x=x.values,
                    y=y.values,
                    t_s=x.t_s(ob.start_ns),
                    x_label=f"{x.name} [{x.unit}]" if x.unit else x.name,
                    y_label=f"{y.name} [{y.unit}]" if y.unit else y.name,
                    title=title,
                    equal_aspect=trajectory and x.unit == y.unit == "m",
                    color_by_time=params.color_by_time,
                    mark_ends=trajectory,
                )
                report = _window_report(ob, lo, hi, title, [_series_out(x), _series_out(y)], notes)
                return self._store(key, png, report)

        return self._plot(XY, params, [params.bag], make, key)

    def xy_series(
        self, ob: OpenBag, params: XYParams, lo: int, hi: int, progress: Progress
    ) -> tuple[PathSeries, PathSeries, list[str]]:
        if params.x is not None and params.y is not None:
            x, y = read_paths(ob, [params.x, params.y], lo, hi, progress)
            if not np.array_equal(x.t_ns, y.t_ns):
                raise ArgumentError("x and y must be fields of the same topic (one point per message)")
            return x, y, []
        if params.x is not None or params.y is not None:
            raise ArgumentError("give both x and y message paths, or only a pose topic (or nothing) for the trajectory")
        topic, msgtype, others = choose_pose_topic(ob, params.topic)
        x, y = positions(ob, topic, msgtype, lo, hi, progress)
        chosen = f"trajectory of {topic}" + (f" (other pose topics: {', '.join(others)})" if others else "")
        gps = ["GPS fixes as metres east and north of the first valid fix"] if is_fix(msgtype) else []
        return x, y, [chosen, *gps]

    def scan(self, params: ScanPlotParams, progress: Progress, key: str | None = None) -> PlotReport:
        def make(key: str) -> PlotReport:
            with self._access.open(params.bag) as ob:
                topic, msgtype = choose_lidar_topic(ob, params.topic)
                if msgtype != SCAN:
                    raise ArgumentError(f"{topic} is {msgtype}; plot_lidar_scan draws LaserScan topics")
                raw = ob.nearest(topic, ob.time(params.time))
                message = ob.reader.decode(raw)
                scan = laser_ranges(message)
                ranges, angles, valid, high = scan.ranges, scan.angles, scan.valid, scan.range_max
                when = ob.instant(raw.log_time_ns)
                title = f"{topic} at {when.offset_s:.2f} s ({ob.name})"
                shown = np.where(valid, ranges, np.nan)
                png = drawing.render_scan(
                    angles_rad=angles, ranges_m=shown, title=title, range_max_m=high, within_m=params.within_m
                )
                closest = float(ranges[valid].min()) if valid.any() else None
                report = PlotReport(
                    bags=[ob.name],
                    title=title,
                    start=when,
                    end=when,
                    series=[
                        SeriesOut(
                            name=f"{topic}.ranges",
                            unit="m",
                            points=int(valid.sum()),
                            min=closest,
                            max=float(ranges[valid].max()) if valid.any() else None,
                        )
                    ],
                    artifact=_PENDING,
                    notes=[f"{int((~valid).sum())} invalid ranges (NaN, inf or outside range_min..range_max) left out"],
                )
                return self._store(key, png, report)

        return self._plot(SCAN_PLOT, params, [params.bag], make, key)

    def histogram(self, params: HistogramParams, progress: Progress, key: str | None = None) -> PlotReport:
        def make(key: str) -> PlotReport:
            with self._access.open(params.bag) as ob:
                lo, hi = ob.window(params.start, params.end)
                series = read_path(ob, params.path, lo, hi, progress)
                title = f"{series.name} ({_window_title(ob, lo, hi)})"
                png = drawing.render_histogram(
                    series.values, bins=params.bins, label=series.name, unit=series.unit, title=title
                )
                return self._store(key, png, _window_report(ob, lo, hi, title, [_series_out(series)]))

        return self._plot(HISTOGRAM, params, [params.bag], make, key)

    def compare(self, params: CompareParams, progress: Progress, key: str | None = None) -> PlotReport:
        def make(key: str) -> PlotReport:
            lines, summaries, notes, names = [], [], [], []
            first_start = first_end = None
            for bag, step in zip(params.bags, spans(progress, len(params.bags)), strict=True):
                aligning, reading = spans(step, 2)
                with self._access.open(bag) as ob:
                    origin = motion_start(ob, aligning) if params.align == "motion" else ob.start_ns
                    if origin is None:
                        notes.append(f"{ob.name}: no motion found, aligned on its start")
                        origin = ob.start_ns
                    series = read_path(ob, params.path, ob.start_ns, ob.end_ns, reading)
                    lines.append(Line(ob.name, series.unit, series.t_s(origin), series.values))
                    summaries.append(_series_out(series).model_copy(update={"name": f"{ob.name}: {series.name}"}))
                    names.append(ob.name)
                    first_start = first_start or ob.instant(ob.start_ns)
                    first_end = first_end or ob.instant(ob.end_ns)
            unit = unit_of(params.path.partition(".")[2])
            label = f"{params.path} [{unit}]" if unit else params.path
            since = "first motion" if params.align == "motion" else "bag start"
            first, last = min(float(line.x.min()) for line in lines), max(float(line.x.max()) for line in lines)
            title = f"{params.path}: {', '.join(names)} ({first:.1f} to {last:.1f} s from each {since})"
            png = drawing.render_overlay(lines, title=title, y_label=label, x_label=f"time from {since} [s]")
            report = PlotReport(
                bags=names,
                title=title,
                start=first_start,
                end=first_end,
                series=summaries,
                artifact=_PENDING,
                notes=notes,
            )
            return self._store(key, png, report)

        return self._plot(COMPARE, params, params.bags, make, key)


_PENDING = Artifact(id="", url="", mime_type="image/png", bytes=0, width=0, height=0)
