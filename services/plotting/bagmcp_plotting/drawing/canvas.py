"""Figure creation, shared styling and deterministic PNG output for every renderer.

Only matplotlib's object API is used (Figure + FigureCanvasAgg, no pyplot, no rcParams changes while
drawing), so renders can run concurrently in worker threads. One rcParam is set once, on import: every text
is drawn literally (``text.parse_math`` off). Titles, labels and legends carry the caller's words and the
bag's topic and field names; with mathtext on, a ``$`` in them was parsed as TeX, and a title of
``$\\frac{$`` answered "internal error".
"""

from __future__ import annotations

import io
import textwrap

import matplotlib
from matplotlib.axes import Axes
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from PIL import Image

from bagmcp_plotting.drawing.fitting import fit_title

WIDTH_IN = 10.0
HEIGHT_IN = 6.0
DPI = 100
TITLE_SIZE = 15
TITLE_CHARS = 100  # a longer title wraps onto more lines (fewer where they are wide: fitting.py)
LABEL_SIZE = 13
TICK_SIZE = 11
LEGEND_SIZE = 11
PNG_BUDGET_BYTES = 190_000
matplotlib.rcParams["text.parse_math"] = False  # see the module's docstring
# matplotlib's tab10 palette, in order.
PALETTE = (
    "#1f77b4",
    "#ff7f0e",
    "#2ca02c",
    "#d62728",
    "#9467bd",
    "#8c564b",
    "#e377c2",
    "#7f7f7f",
    "#bcbd22",
    "#17becf",
)


def new_figure(*, title: str, width_in: float = WIDTH_IN, height_in: float = HEIGHT_IN) -> Figure:
    """A constrained-layout figure with its own Agg canvas and the given title."""
    figure = Figure(figsize=(width_in, height_in), dpi=DPI, layout="constrained")
    FigureCanvasAgg(figure)
    figure.suptitle(textwrap.fill(title, width=TITLE_CHARS), fontsize=TITLE_SIZE)
    fit_title(figure, title)
    return figure


def style_axes(axes: Axes, *, x_label: str | None, y_label: str | None, grid: bool = True) -> None:
    """Readable label and tick sizes plus a light grid."""
    if x_label is not None:
        axes.set_xlabel(x_label, fontsize=LABEL_SIZE)
    if y_label is not None:
        axes.set_ylabel(y_label, fontsize=LABEL_SIZE)
    axes.tick_params(labelsize=TICK_SIZE)
    if grid:
        axes.grid(visible=True, alpha=0.35)


def axis_label(name: str, unit: str | None) -> str:
    """'name [unit]', or just the name when the unit is unknown."""
    return f"{name} [{unit}]" if unit else name


def to_png(figure: Figure) -> bytes:
    """PNG bytes without a Software tag, so identical input gives identical bytes.

    A plot that would exceed PNG_BUDGET_BYTES (very dense noisy data) is re-encoded with a 256-colour palette.
    """
    out = io.BytesIO()
    figure.savefig(out, format="png", dpi=DPI, metadata={"Software": None})
    if out.tell() <= PNG_BUDGET_BYTES:
        return out.getvalue()
    with Image.open(out) as image:
        palette = image.convert("RGB").quantize(colors=256, method=Image.Quantize.MEDIANCUT, dither=Image.Dither.NONE)
    small = io.BytesIO()
    palette.save(small, format="PNG", optimize=True)
    return small.getvalue()
