"""Drawing plots with matplotlib (Agg, object API only): the public entry points.

Every renderer returns PNG bytes (10x6 in at 100 dpi unless stated) that are identical for identical input.
"""

from __future__ import annotations

from bagmcp_plotting.drawing.histogram import histogram_legend, render_histogram
from bagmcp_plotting.drawing.layout import Layout, layout_for
from bagmcp_plotting.drawing.lines import Line, summary_of
from bagmcp_plotting.drawing.scan import render_scan
from bagmcp_plotting.drawing.timeseries import render_overlay, render_timeseries
from bagmcp_plotting.drawing.xy import render_xy

__all__ = [
    "Layout",
    "Line",
    "histogram_legend",
    "layout_for",
    "render_histogram",
    "render_overlay",
    "render_scan",
    "render_timeseries",
    "render_xy",
    "summary_of",
]
