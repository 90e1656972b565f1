"""Text that fits the figure: titles wrapped and legends narrowed by measuring them, not by counting characters.

A title wrapped at a fixed 100 characters ran off both sides of a 10 in figure (15 pt text is about 11 px a
character); a legend of three long paths in four columns ran off both sides too. Each is now measured after
constrained layout (one layout pass, 15-40 ms a plot) and redone narrower until its box lies inside the figure:
the title wraps at the measured width (long paths break anywhere), a legend drops columns, then shrinks its text
to LEGEND_MIN_SIZE, then shortens labels in the middle (a path keeps its start and its field).

Titles and legends are measured without laying the figure out: the title is centred and a figure legend is
anchored to the figure's edges, so constrained layout moves neither sideways nor a legend at all (it makes room
for them). Measuring after a layout pass gave the same boxes but cost a full layout per try (4.4 s of the unit
tests' 77 s of CPU, about 40 ms a plot with a legend); without it the final layout starts from a fresh figure,
which moved some lines by a fraction of a pixel (0.1 % of pixels differed, by at most 12 of 765 levels).
``texts_outside`` does lay out, as axis labels and titles move with the axes.
"""

from __future__ import annotations

import textwrap
from collections.abc import Sequence
from typing import Literal

from matplotlib.artist import Artist
from matplotlib.backends.backend_agg import RendererAgg
from matplotlib.figure import Figure
from matplotlib.legend import Legend
from matplotlib.text import Text
from matplotlib.transforms import Bbox

MARGIN_PX = 2.0
LEGEND_MIN_SIZE = 8
TRIES = 6
LegendPlace = Literal["outside lower center", "upper right"]


def _renderer(figure: Figure) -> RendererAgg:
    """The renderer that measures text, without drawing (see the module docstring)."""
    renderer = figure.canvas.get_renderer()  # type: ignore[attr-defined]
    assert isinstance(renderer, RendererAgg)
    return renderer


def _laid_out(figure: Figure) -> RendererAgg:
    figure.draw_without_rendering()  # runs constrained layout, so boxes are where they will be drawn
    return _renderer(figure)


def _inside(box: Bbox, figure: Figure) -> bool:
    frame = figure.bbox
    return bool(
        box.x0 >= frame.x0 - MARGIN_PX
        and box.x1 <= frame.x1 + MARGIN_PX
        and box.y0 >= frame.y0 - MARGIN_PX
        and box.y1 <= frame.y1 + MARGIN_PX
    )


def _title(figure: Figure) -> Text | None:
    wanted = figure.get_suptitle()
    found = [c for c in figure.get_children() if isinstance(c, Text) and wanted and c.get_text() == wanted]
    return found[0] if found else None


def fit_title(figure: Figure, title: str) -> None:
    """Wrap the figure's title so each line fits its width."""
    width_chars = max(len(title), 1)
    for _ in range(TRIES):
        text = _title(figure)
        if text is None:
            return
        box = text.get_window_extent(_renderer(figure))
        if box.width <= figure.bbox.width - 2 * MARGIN_PX:
            return
        longest = max(len(line) for line in text.get_text().splitlines())
        width_chars = max(int(longest * (figure.bbox.width - 4 * MARGIN_PX) / box.width), 10)
        lines = textwrap.wrap(title, width=width_chars, break_long_words=True, break_on_hyphens=False)
        figure.suptitle("\n".join(lines), fontsize=text.get_fontsize())


def _shortened(label: str, ratio: float) -> str:
    keep = max(int(len(label) * ratio) - 1, 8)
    if keep >= len(label):
        return label
    head = keep // 2
    return f"{label[:head]}…{label[len(label) - (keep - head - 1) :]}"


def add_legend(
    figure: Figure, entries: Sequence[tuple[Artist, str]], *, loc: LegendPlace, columns: int, fontsize: float
) -> Legend:
    """A figure legend of ``entries`` that lies inside the figure (see the module docstring)."""
    labels = [label for _, label in entries]
    size = fontsize
    legend = _legend(figure, entries, labels, loc=loc, columns=columns, size=size)
    for _ in range(TRIES * 3):
        box = legend.get_window_extent(_renderer(figure))
        if _inside(box, figure):
            return legend
        if columns > 1:
            columns = max(columns // 2, 1)
        elif size > LEGEND_MIN_SIZE:
            size = max(size - 2, LEGEND_MIN_SIZE)
        else:
            labels = [_shortened(label, (figure.bbox.width - 4 * MARGIN_PX) / box.width) for label in labels]
        legend.remove()
        legend = _legend(figure, entries, labels, loc=loc, columns=columns, size=size)
    return legend


def texts_outside(figure: Figure) -> list[str]:
    """The title, figure texts, axis labels and legends whose boxes leave the figure (empty when all fit).

    Tick labels are left to matplotlib: those off the axis range exist as hidden texts beyond the figure."""
    renderer = _laid_out(figure)
    texts = [t for t in (_title(figure), *figure.texts) if t is not None]
    for axes in figure.axes:
        texts += [axis.label for axis in (axes.xaxis, axes.yaxis) if axis.get_visible()] + [axes.title]
    legends = [*figure.legends, *(a.get_legend() for a in figure.axes)]
    found = [t.get_text() for t in texts if t.get_text().strip() and not _inside(t.get_window_extent(renderer), figure)]
    found += [f"legend {i}" for i, g in enumerate(legends) if g and not _inside(g.get_window_extent(renderer), figure)]
    return found


def _legend(
    figure: Figure,
    entries: Sequence[tuple[Artist, str]],
    labels: list[str],
    *,
    loc: LegendPlace,
    columns: int,
    size: float,
) -> Legend:
    made: Legend = figure.legend(handles=[a for a, _ in entries], labels=labels, loc=loc, ncols=columns, fontsize=size)
    return made
