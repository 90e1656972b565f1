"""The data an MCP Apps viewer (and the web console) draws, added to a finished tool answer.

A view is a plain JSON dict ``{"kind": ..., ...}`` in the result's ``_meta["bagmcp/view"]``. It is built in
a worker thread after the answer (a job still running gets none), only for a caller that draws it (an Apps
client, named by the gateway with ``_meta["bagmcp/views"]`` on the request, or one connected directly), so
other clients pay nothing for it; and bounded: series are thinned by the caller to a few thousand points,
scans to at most ``MAX_RANGES`` ranges, so a view stays under ~300 KB."""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable
from typing import Any

import anyio
import numpy as np
import numpy.typing as npt
from mcp.server.apps import client_supports_apps
from mcp.server.mcpserver import Context
from mcp.types import CallToolResult

from bagmcp_kit.web.viewers import VIEWS_META_KEY, with_view
from bagmcp_shared.laser_ranges import laser_ranges

View = dict[str, Any]
MAX_RANGES = 1440


def numbers(values: Iterable[float] | npt.NDArray[np.float64]) -> list[float | None]:
    """JSON numbers; NaN and infinities (not JSON) become null, which the views leave out."""
    return [float(v) if math.isfinite(v) else None for v in np.asarray(values, dtype=np.float64).tolist()]


def thin_indices(count: int, *, max_points: int) -> npt.NDArray[np.intp]:
    """At most ``max_points`` evenly spaced indices of ``count`` points, the first and last included."""
    if count <= max_points:
        return np.arange(count, dtype=np.intp)
    return np.unique(np.linspace(0, count - 1, max_points).round().astype(np.intp))


def finished(answer: CallToolResult) -> bool:
    content = answer.structured_content
    return not answer.is_error and isinstance(content, dict) and content.get("result") is not None


def wants_views(ctx: Context) -> bool:
    """Whether the caller draws views: the gateway says so for its caller, a direct client by its capabilities."""
    meta = ctx.request_context.meta or {}
    return bool(meta.get(VIEWS_META_KEY)) or client_supports_apps(ctx)


async def add_view(ctx: Context, answer: CallToolResult, make: Callable[[], View | None]) -> CallToolResult:
    """``answer`` with the view ``make`` builds (in a thread) when the work is done and the caller draws
    views; unchanged otherwise."""
    if not finished(answer) or not wants_views(ctx):
        return answer
    view = await anyio.to_thread.run_sync(make)
    if view is not None:
        answer.meta = with_view(answer.meta, view)
    return answer


def scan_entry(message: Any, *, offset_s: float) -> View:
    """One LaserScan for the polar view: ranges outside range_min..range_max become null; more than
    ``MAX_RANGES`` rays keep every k-th (the angle step grows to match)."""
    scan = laser_ranges(message)
    shown = np.where(scan.valid, scan.ranges, np.nan)
    step = max(1, math.ceil(shown.size / MAX_RANGES))
    return {
        "t": round(offset_s, 6),
        "angle_min": scan.angle_min,
        "angle_increment": scan.angle_increment * step,
        "range_max": scan.range_max,
        "ranges": numbers(shown[::step]),
    }
