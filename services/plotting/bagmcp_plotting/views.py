"""What the plots look like to an MCP Apps viewer and the web console: the numbers of each plot, read again
(indexed paths read in milliseconds) and thinned the way the PNG is, as ``{"kind": ...}`` view dicts
(kit/web/view_data.py). Built only for an answer with its image, never for a job still running."""

from __future__ import annotations

import numpy as np

from bagmcp_kit.web.view_data import View, numbers, scan_entry
from bagmcp_plotting.data import PathSeries, read_path, read_paths
from bagmcp_plotting.drawing.bins import freedman_diaconis_bins
from bagmcp_plotting.drawing.decimate import extreme_indices, minmax_decimate
from bagmcp_plotting.plots import CompareParams, HistogramParams, Plotter, ScanPlotParams, TimeseriesParams, XYParams
from bagmcp_plotting.positions import motion_start
from bagmcp_shared.access import BagAccess, OpenBag
from bagmcp_shared.jobs import Unreported
from bagmcp_shared.topics import choose_lidar_topic

COLUMNS = 1500  # per series: at most 3000 points (each column's min and max), as the PNG draws
PATH_POINTS = 4000


def _series(name: str, unit: str | None, t_s: np.ndarray, values: np.ndarray) -> View:
    t, v = minmax_decimate(t_s, values, columns=COLUMNS)
    return {"name": name, "unit": unit, "t": numbers(t), "v": numbers(v)}


def _of(series: PathSeries, ob: OpenBag) -> View:
    return _series(series.name, series.unit, series.t_s(ob.start_ns), series.values)


class PlotViews:
    def __init__(self, access: BagAccess, plotter: Plotter) -> None:
        self._access = access
        self._plotter = plotter

    def timeseries(self, params: TimeseriesParams, title: str) -> View:
        with self._access.open(params.bag) as ob:
            lo, hi = ob.window(params.start, params.end)
            series = read_paths(ob, params.paths, lo, hi, Unreported())
            return {
                "kind": "timeseries",
                "title": title,
                "style": params.style,
                "series": [_of(s, ob) for s in series],
            }

    def xy(self, params: XYParams, title: str) -> View:
        with self._access.open(params.bag) as ob:
            lo, hi = ob.window(params.start, params.end)
            x, y, _ = self._plotter.xy_series(ob, params, lo, hi, Unreported())
            keep = extreme_indices(x.values, y.values, max_points=PATH_POINTS)
            return {
                "kind": "xy",
                "title": title,
                "x": numbers(x.values[keep]),
                "y": numbers(y.values[keep]),
                "t": numbers(x.t_s(ob.start_ns)[keep]),
                "x_label": f"{x.name} [{x.unit}]" if x.unit else x.name,
                "y_label": f"{y.name} [{y.unit}]" if y.unit else y.name,
                "equal_aspect": params.x is None and x.unit == y.unit == "m",
                "stops": [],
            }

    def scan(self, params: ScanPlotParams, title: str) -> View:
        with self._access.open(params.bag) as ob:
            topic, _ = choose_lidar_topic(ob, params.topic)
            raw = ob.nearest(topic, ob.time(params.time))
            entry = scan_entry(ob.reader.decode(raw), offset_s=(raw.log_time_ns - ob.start_ns) / 1e9)
            return {
                "kind": "scan",
                "title": title,
                "range_max_m": entry["range_max"],
                "within_m": params.within_m,
                "scans": [entry],
            }

    def histogram(self, params: HistogramParams, title: str) -> View:
        with self._access.open(params.bag) as ob:
            lo, hi = ob.window(params.start, params.end)
            series = read_path(ob, params.path, lo, hi, Unreported())
        finite = series.values[np.isfinite(series.values)]
        counts, edges = np.histogram(finite, bins=params.bins or freedman_diaconis_bins(finite))
        return {
            "kind": "histogram",
            "title": title,
            "name": series.name,
            "unit": series.unit,
            "edges": numbers(edges),
            "counts": [int(c) for c in counts],
        }

    def compare(self, params: CompareParams, title: str) -> View:
        lines = []
        for bag in params.bags:
            with self._access.open(bag) as ob:
                origin = motion_start(ob, Unreported()) if params.align == "motion" else None
                series = read_path(ob, params.path, ob.start_ns, ob.end_ns, Unreported())
                lines.append(_series(ob.name, series.unit, series.t_s(origin or ob.start_ns), series.values))
        return {"kind": "timeseries", "title": title, "style": "line", "series": lines}
