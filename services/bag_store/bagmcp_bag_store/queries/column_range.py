"""get_messages_in_range in columns: numeric fields over a window as arrays (``{"t": [...], "x": [...]}``),
thinned by ``every`` and ``max_points`` without losing any field's extremes, within the byte budget."""

from __future__ import annotations

import itertools
import json
import math

import numpy as np
import numpy.typing as npt

from bagmcp_bag_store.queries.messages import MessageRangeParams, time_base
from bagmcp_bag_store.reports import MessageRange
from bagmcp_shared.access import BagAccess
from bagmcp_shared.errors import ArgumentError
from bagmcp_shared.index import read_series
from bagmcp_shared.paths import check_steps, format_steps, parse_field_path

DEFAULT_POINTS = 1000  # when layout=columns comes without max_points
SIGNIFICANT = 5  # significant digits kept of each value (the answer says so)


def _bucket_extremes(values: list[npt.NDArray[np.float64]], buckets: int) -> set[int]:
    count = len(values[0])
    keep: set[int] = set()
    for start, stop in itertools.pairwise(np.linspace(0, count, buckets + 1).astype(np.intp)):
        for column in values:
            chunk = column[start:stop]
            if np.isfinite(chunk).any():
                keep.update((int(start + np.nanargmin(chunk)), int(start + np.nanargmax(chunk))))
            elif stop > start:
                keep.add(int(start))
    return keep


def keep_extremes(values: list[npt.NDArray[np.float64]], max_points: int) -> npt.NDArray[np.intp]:
    """Indexes of at most ``max_points`` samples, in time order: per bucket of consecutive samples the
    minimum and the maximum of every column, so no column loses a peak, with as many buckets as fit."""
    count = len(values[0]) if values else 0
    if count <= max_points:
        return np.arange(count)
    buckets = max(max_points // 2, 1)
    keep = _bucket_extremes(values, buckets)
    while len(keep) > max_points and buckets > 1:
        buckets = max(int(buckets * max_points / len(keep)) - 1, 1)
        keep = _bucket_extremes(values, buckets)
    for index in np.linspace(0, count - 1, max_points).astype(np.intp):  # fill what is left evenly
        if len(keep) >= max_points:
            break
        keep.add(int(index))
    return np.asarray(sorted(keep), dtype=np.intp)


def _number(value: float) -> float | int | None:
    """A value to ``SIGNIFICANT`` digits, written as an integer when it is one (shorter JSON)."""
    if not math.isfinite(value):
        return None
    rounded = float(f"{value:.{SIGNIFICANT}g}")
    return int(rounded) if rounded.is_integer() and abs(rounded) < 1e15 else rounded


def _seconds(offset_ns: int) -> float | int:
    """Seconds to 1 ms, as an integer when whole."""
    value = round(offset_ns / 1e9, 3)
    return int(value) if value.is_integer() else value


def _size(t: list[float | int], columns: dict[str, list[float | int | None]]) -> int:
    return len(json.dumps({"t": t, "columns": columns}, separators=(",", ":")))


def messages_as_columns(access: BagAccess, params: MessageRangeParams, *, budget_bytes: int) -> MessageRange:
    """Max_points with layout=messages (``asked_messages``) only columns can honour, so the answer comes in
    columns and says so (or the error says how to thin whole messages instead)."""
    fields, every = params.fields or [], params.every
    max_points, asked_messages = params.max_points or DEFAULT_POINTS, params.layout == "messages"
    why = "max_points (it thins numeric fields, in layout=columns)" if asked_messages else "layout=columns"
    if not fields:
        raise ArgumentError(
            f"{why} needs `fields`: the numeric message paths to return, e.g. ['twist.twist.linear.x']"
            + ("; to thin whole messages, pass every=N instead" if asked_messages else "")
        )
    with access.open(params.bag) as ob:
        name = ob.topic_name(params.topic)
        msgtype = ob.msgtype(name)
        store = ob.reader.decoder.typestore(msgtype)
        paths = [format_steps(parse_field_path(f)) for f in fields]
        for path in paths:
            check_steps(store, msgtype, parse_field_path(path))
        lo, hi = ob.window(params.start, params.end)
        series = read_series(ob.reader, name, paths, index=ob.index, start_ns=lo, stop_ns=hi + 1)
        try:
            arrays = [series.columns[p].astype(np.float64)[::every] for p in paths]
        except (TypeError, ValueError) as err:
            raise ArgumentError(
                f"{why} takes numeric fields only ({err}); use layout=messages"
                + (" with every=N to thin" if asked_messages else "")
            ) from err
        times = series.t_ns[::every]
        chosen = keep_extremes(arrays, max_points)
        said = ["max_points thins numeric fields, so this answer is in layout=columns"] if asked_messages else []
        notes = said
        while True:
            t = [_seconds(int(times[i]) - ob.start_ns) for i in chosen]
            columns = {p: [_number(float(a[i])) for i in chosen] for p, a in zip(paths, arrays, strict=True)}
            size = _size(t, columns)
            if size <= budget_bytes or len(chosen) <= 2:
                break
            chosen = keep_extremes(arrays, max(int(len(chosen) * budget_bytes / size * 0.97), 2))
            fitted = f"thinned to {len(chosen)} points to fit {budget_bytes} bytes; narrow the window for more"
            notes = [*said, fitted]
        return MessageRange(
            bag=ob.name,
            topic=name,
            start=ob.instant(lo),
            end=ob.instant(hi),
            clock="log_time",
            time_base=time_base(ob),
            total=len(series.t_ns),
            returned=len(t),
            truncated=False,
            next_cursor=None,
            messages=[],
            t=t,
            columns=columns,
            digits=SIGNIFICANT,
            downsampled=len(t) < len(series.t_ns),
            notes=notes,
        )
