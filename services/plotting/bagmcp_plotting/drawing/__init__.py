"""Drawing plots with matplotlib (Agg, object API only): the public entry points.

Every renderer returns PNG bytes (10x6 in at 100 dpi unless stated) that are identical for identical input.

The renderers load on first use (PEP 562 ``__getattr__``): importing them (matplotlib, PIL) costs a process
about 0.43 s of CPU (median of 7, time in a plotting worker after its own imports; its whole import went from
2.37 to 1.70 s), and the plotting service and worker start, and answer stored plots and the viewers' data,
without drawing anything. So callers reach a renderer as ``drawing.render_xy(...)`` at call time; the helpers
that only count (lines, layout, bins) load with the package. Under Celery's prefork pool (compose,
``make stack``) each child that renders pays the import once, where the parent paid it once before forking.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING

from bagmcp_plotting.drawing.layout import Layout, layout_for
from bagmcp_plotting.drawing.lines import Line, summary_of

if TYPE_CHECKING:
    from bagmcp_plotting.drawing.histogram import histogram_legend, render_histogram
    from bagmcp_plotting.drawing.scan import render_scan
    from bagmcp_plotting.drawing.timeseries import render_overlay, render_timeseries
    from bagmcp_plotting.drawing.xy import render_xy

# Each renderer's module in this package (each imports matplotlib).
_RENDERERS = {
    "histogram_legend": "histogram",
    "render_histogram": "histogram",
    "render_scan": "scan",
    "render_overlay": "timeseries",
    "render_timeseries": "timeseries",
    "render_xy": "xy",
}

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


def __getattr__(name: str) -> object:
    """A renderer, imported (with matplotlib) the first time it is asked for."""
    module = _RENDERERS.get(name)
    if module is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    return getattr(importlib.import_module(f"{__name__}.{module}"), name)
